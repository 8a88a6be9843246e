"""The chosen design in motion: the simulated payload test, the time-optimal cycle (TOPP-RA), the
front's cycles and the torques with the printed links."""
