"""Boston Dynamics Spot with the Spot Arm."""
