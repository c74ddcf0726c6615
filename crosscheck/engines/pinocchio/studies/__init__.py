"""pinocchio's own studies."""
