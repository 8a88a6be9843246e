"""Parts you can build: bearings and bores at the joints, the bored link outlines and their mass,
printability (the one fit rule), and the bill of materials."""
