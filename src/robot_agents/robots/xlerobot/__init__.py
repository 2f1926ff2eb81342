"""XLeRobot (Vector-Wangel): two SO-100 arms and a pan-tilt head on a cart."""
