"""The final record of the machine as built: its time-optimal cycle checked (placing error,
strength, drives' thermal use)."""
