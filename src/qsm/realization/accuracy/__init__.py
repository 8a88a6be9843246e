"""How precisely the realised arm places its payload: the accuracy budget and the sections and
gearboxes sized for the tolerance."""
