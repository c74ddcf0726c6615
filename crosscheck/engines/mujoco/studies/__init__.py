"""mujoco's own studies."""
