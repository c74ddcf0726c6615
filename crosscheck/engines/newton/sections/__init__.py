"""Report sections of the Newton engines."""
