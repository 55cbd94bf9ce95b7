"""The paper: every number it states, the rows that put ours beside them, and the table."""
