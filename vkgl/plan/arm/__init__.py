"""The arm's paths for a candidate plan: straight moves into and out of contacts, contact chains, transits."""
