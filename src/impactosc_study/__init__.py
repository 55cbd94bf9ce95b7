"""The paper's study on top of the library: the paper's numbers and the rows that compare with
them, the figure makers, the noise and coverage studies, and the workflow's configuration."""
