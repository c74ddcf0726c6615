"""pinocchio's own sections."""
