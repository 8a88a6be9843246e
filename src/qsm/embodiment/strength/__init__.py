"""Whether a design's links hold their loads: joint loads by Newton-Euler, the beam model and
stresses of every link, sections sized by strength, the check's record, verdict and advice."""
