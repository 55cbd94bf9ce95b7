"""The paper: every number it states (numbers), the rows that put ours beside them (rows),
and the table they make (table)."""
