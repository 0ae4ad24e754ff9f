"""The checks of scene geometry: where bodies start (placed on the table, relative to another body, or open on
their joints), where goals, regions and keep-out regions put them, and what clears an overlap."""
