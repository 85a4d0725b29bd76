"""Where recordings are: local paths, or URLs read through fsspec (``tftools[fleet]``, imported only
for a URL by ``remote``) as local sparse copies that the readers fill range by range (``source``)."""

from tftools.sources.storage.locations import BAG_SUFFIXES, expand, is_url, local_recording, recordings_in

__all__ = ["BAG_SUFFIXES", "expand", "is_url", "local_recording", "recordings_in"]
