"""The command line ``impactosc``: one module per command group, one home for the parsers."""
