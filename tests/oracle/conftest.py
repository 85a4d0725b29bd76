"""The corpus fixture, for the MessageFilter comparison on real recordings."""

from tests.corpus.conftest import corpus  # noqa: F401
