"""ANYbotics legged robots."""
