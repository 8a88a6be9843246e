"""The builder's kit: base, hubs, pins, tool flange and fasteners, checked; their layout, steps,
BOM and files; the plates and STLs built with it."""
