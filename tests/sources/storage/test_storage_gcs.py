"""``gs://`` recordings on a real Google Cloud Storage API server (gcp-storage-emulator, on 127.0.0.1):
a bucket of ROS1, .db3 and .mcap recordings and an image bag, read as their local copies are, the
image bag through ranged reads of its transforms alone."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.sources.bag.test_ros1 import interleaved, rosbag_available  # noqa: F401 (a fixture)
from tests.sources.ros1_helpers import write_rosbag
from tests.sources.storage.test_storage_s3 import IMAGE_BYTES, IMAGES, fleet, free_port, server_on, tfx  # noqa: F401 (a fixture)

pytestmark = pytest.mark.slow
NO_GRPC = {"GCSFS_EXPERIMENTAL_ZB_HNS_SUPPORT": "false"}


@pytest.fixture(scope="module")
def gcs_env() -> Iterator[dict[str, str]]:
    """The emulator on a free port of 127.0.0.1 (in memory), and the environment gcsfs finds it by."""
    port = free_port()
    command = [sys.executable, "-m", "gcp_storage_emulator", "start", "--host", "127.0.0.1", "--port", str(port)]
    with server_on(port, [*command, "--in-memory"], "the GCS emulator"):
        # The emulator speaks JSON over HTTP only: gcsfs's gRPC probe of a bucket's kind would wait 60 s.
        yield {**os.environ, "STORAGE_EMULATOR_HOST": f"http://127.0.0.1:{port}", **NO_GRPC}


def test_wtf_reads_a_gcs_bucket_as_the_local_copies(
    rosbag_available: None,  # noqa: F811
    gcs_env: dict[str, str],
    fleet: Path,  # noqa: F811
) -> None:
    image_bag = write_rosbag(fleet / "images.bag", interleaved(IMAGES, IMAGE_BYTES), "none")
    upload = (
        "import sys, gcsfs; fs = gcsfs.GCSFileSystem(token='anon', project='test'); fs.mkdir('bucket');"
        " fs.put(sys.argv[1], 'bucket/fleet', recursive=True)"
    )
    subprocess.run([sys.executable, "-c", upload, str(fleet)], env=gcs_env, check=True, timeout=120)
    remote = tfx("wtf", "gs://bucket/fleet/", "--format", "json", env=gcs_env)
    local = tfx("wtf", f"{fleet}/", "--format", "json", env=gcs_env)
    assert remote.returncode == local.returncode == 1, remote.stderr  # the corrupt bag fails the fleet
    got, expected = json.loads(remote.stdout)["bags"], json.loads(local.stdout)["bags"]
    assert [b["paths"][0] for b in got] == [
        p.replace(f"{fleet}/", "gs://bucket/fleet/") for b in expected for p in b["paths"]
    ]
    for mine, theirs in zip(got[1:], expected[1:], strict=True):
        said = f"{mine.get('error')} {mine.get('problems')}"  # whole: pytest cuts a dict's repr short
        assert mine["transforms"] == theirs["transforms"] and mine["findings"] == theirs["findings"], said
    (images,) = next(b for b in got if b["paths"][0].endswith("images.bag"))["fetched"]
    assert images["size"] == image_bag.stat().st_size and images["received"] < 0.05 * images["size"]
