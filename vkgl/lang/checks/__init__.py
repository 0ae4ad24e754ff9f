"""The semantic checks: one validator over a whole compilation."""
