"""``gs://`` recordings on a real Google Cloud Storage API server (gcp-storage-emulator, on 127.0.0.1):
a bucket of ROS1, .db3 and .mcap recordings and an image bag, read as their local copies are, the
image bag through ranged reads of its transforms alone."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.sources.ros1_helpers import write_rosbag
from tests.sources.test_ros1 import interleaved, rosbag_available  # noqa: F401 (a fixture)
from tests.sources.test_storage_s3 import IMAGE_BYTES, IMAGES, fleet, free_port, tfx  # noqa: F401 (a fixture)

pytestmark = pytest.mark.slow
NO_GRPC = {"GCSFS_EXPERIMENTAL_ZB_HNS_SUPPORT": "false"}


@pytest.fixture(scope="module")
def gcs_env() -> Iterator[dict[str, str]]:
    """The emulator on a free port of 127.0.0.1 (in memory), and the environment gcsfs finds it by."""
    port = free_port()
    command = [sys.executable, "-m", "gcp_storage_emulator", "start", "--host", "127.0.0.1", "--port", str(port)]
    server = subprocess.Popen([*command, "--in-memory"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 30
        while True:
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError:
                assert time.monotonic() < deadline and server.poll() is None, "the GCS emulator did not start"
                time.sleep(0.2)
        # The emulator speaks JSON over HTTP only: gcsfs's gRPC probe of a bucket's kind would wait 60 s.
        yield {**os.environ, "STORAGE_EMULATOR_HOST": f"http://127.0.0.1:{port}", **NO_GRPC}
    finally:
        server.terminate()
        server.wait(timeout=10)


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
        assert mine["transforms"] == theirs["transforms"] and mine["findings"] == theirs["findings"]
    (images,) = next(b for b in got if b["paths"][0].endswith("images.bag"))["fetched"]
    assert images["size"] == image_bag.stat().st_size and images["received"] < 0.05 * images["size"]
