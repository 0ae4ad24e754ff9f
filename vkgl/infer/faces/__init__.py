"""What the pushes on a body's faces tell besides its motion: where along a face the contact may be (`family.py`)
and the heights that tip it (`tipping.py`)."""
