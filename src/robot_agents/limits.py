"""Sanity bounds the library enforces on simulated motion."""

#: A joint speed (rad/s or m/s) no robot reaches: a state with a faster joint is refused,
#: and a step whose joint-velocity vector is longer counts as unstable even before
#: MuJoCo's own guard (1e10) resets the env.
MAX_SPEED = 1e4
