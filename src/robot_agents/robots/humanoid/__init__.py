"""The classic MuJoCo capsule humanoid (a simulated character, not a product)."""
