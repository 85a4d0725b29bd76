"""Renderers: analyses turned into text, JSON, CSV, YAML, and graphs."""
