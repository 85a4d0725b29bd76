"""Where recordings are: local paths, or URLs read through fsspec (``tftools[fleet]``) with ranged reads.

``locations`` names recordings (a glob or a prefix expands to those below it) without importing
fsspec; ``remote`` (imported only for a URL) makes each remote file a local sparse copy that the
readers fill range by range through ``copies``.
"""

from tftools.sources.storage.locations import BAG_SUFFIXES, expand, is_url, local_recording, recordings_in

__all__ = ["BAG_SUFFIXES", "expand", "is_url", "local_recording", "recordings_in"]
