"""Model BC: its parameters, its equations and the model files a rig's model travels in."""

from impactosc._lazy import export

export(
    globals(),
    {
        "ModelParams": "impactosc.model.parameters",
        "UntestedParameterWarning": "impactosc.model.parameters",
        "PARAMETERS": "impactosc.model.parameters",
        "ModelFile": "impactosc.model.model_file",
        "read_model_file": "impactosc.model.model_file",
        "write_model_file": "impactosc.model.model_file",
        "resolve_model": "impactosc.model.model_file",
        "apply_overrides": "impactosc.model.model_file",
    },
)
