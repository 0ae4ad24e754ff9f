"""The planning problem read once from the IR (`Problem`), what a re-solve must avoid, and why a sequence is
rejected (`Rejection`)."""
