"""Text <-> one syntax tree for both syntaxes; no semantics."""
