"""Off-line <-> on-line: small named passes over the tree and the world."""
