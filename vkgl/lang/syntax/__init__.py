"""Source text to IR and back: reading files, the parser and builder, syntax errors, the printer."""
