"""Files the package writes and reads: run files, tables, JSON, provenance, atomic writes."""
