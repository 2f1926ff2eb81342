"""Unitree robots."""
