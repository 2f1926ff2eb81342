"""From model files to one compiled MuJoCo model: loading, robot editing, scene composition."""
