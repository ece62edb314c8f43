"""What the verbs do, as library calls (see docs/architecture.md)."""
