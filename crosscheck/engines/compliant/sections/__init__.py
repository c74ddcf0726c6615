"""compliant's own sections."""
