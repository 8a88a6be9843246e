"""How precisely the arm places its payload: the closed chain as a planar frame (the tool's
compliance), its first natural frequency, and the placing error's terms (sag, lost motion)."""
