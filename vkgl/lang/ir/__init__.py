"""The typed IR, its units and plausible limits, the compiled `Program`, and the geometry of its bodies."""
