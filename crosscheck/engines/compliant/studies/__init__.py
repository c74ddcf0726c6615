"""compliant's own studies."""
