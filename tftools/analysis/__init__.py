"""Analyses over a buffer: echo series, frame summaries, monitor statistics, wtf checks."""
