"""Sanity bounds the library enforces on simulated motion."""

#: A joint speed (rad/s or m/s) no robot reaches: a state above it is refused, and a step
#: that reaches it counts as unstable even before MuJoCo's own guard (1e10) resets the env.
MAX_SPEED = 1e4
