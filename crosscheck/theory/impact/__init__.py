"""At a jam and after it: the impact without collision (``darboux_keller``: the impulse integrated in normal
impulse) and the rigid model continued through it (``continuation``: slip, jam, impact, then stick, lift-off or
slip again)."""
