"""K-Scale Labs robots."""
