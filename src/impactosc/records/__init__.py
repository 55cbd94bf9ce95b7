"""Measured records: reading and writing them (CSV, HDF5, TDMS; whole or in chunks), extracting impact events from
sampled displacement, the obstacle's position, and the labelled surrogate (the model sampled
like a rig)."""

from impactosc._lazy import export

export(
    globals(),
    {
        "Record": "impactosc.records.record",
        "record_from_samples": "impactosc.records.record",
        "read_record": "impactosc.records.formats",
        "write_record": "impactosc.records.formats",
        "read_records": "impactosc.records.formats",
        "read_record_set": "impactosc.records.formats",
        "write_record_set": "impactosc.records.formats",
        "open_record_stream": "impactosc.records.streams",
        "RecordStream": "impactosc.records.streams",
        "RecordChunk": "impactosc.records.streams",
        "ExtractOptions": "impactosc.records.extract",
        "extract_events": "impactosc.records.extract",
        "crossing_time_crb": "impactosc.records.impact_times",
        "estimate_x_impact": "impactosc.records.obstacle_estimate",
        "poincare_points": "impactosc.records.poincare",
        "sweep_segments": "impactosc.records.slow_sweep",
        "SurrogateOptions": "impactosc.records.surrogate",
        "surrogate_record": "impactosc.records.surrogate",
        "surrogate_run": "impactosc.records.surrogate",
        "surrogate_driven": "impactosc.records.surrogate",
        "write_long_surrogate": "impactosc.records.long_surrogate",
        "warm_up_kernels": "impactosc.records.warm_up",
    },
)
