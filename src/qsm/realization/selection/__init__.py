"""The design to realise and its realisation: the choice, the sized and bored parts, drives and
bearings, and the machine record (one file every later rule reads)."""
