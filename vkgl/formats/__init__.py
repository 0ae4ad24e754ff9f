"""The external contracts, one module each, the only reader and writer of each: trials, plan, execution report."""
