"""Model BC: its parameters, its equations and the model files a rig's model travels in."""
