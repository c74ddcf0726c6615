"""mujoco's own sections."""
