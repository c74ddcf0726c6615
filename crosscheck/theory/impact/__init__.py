"""At a jam or a GB point and after it: the impact without collision (``darboux_keller``: the impulse integrated in
normal impulse, its limit p -> 0- on p = 0) and the rigid model continued through it (``continuation``: slip, jam
or GB, impact, then stick, lift-off or slip again)."""
