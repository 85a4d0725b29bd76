"""``tfx wtf`` on recordings in a real S3 API server (moto's, on 127.0.0.1) and on an HTTP server
with ranged reads: ROS1, .db3 and .mcap recordings, a corrupt one and an image bag, of which only
the index and the transforms' ranges are fetched."""

from __future__ import annotations

import http.server
import json
import os
import re
import shutil
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

from tests.cli.conftest import SAMPLE_BAGS
from tests.sources.bag.test_ros1 import interleaved, rosbag_available  # noqa: F401 (a fixture)
from tests.sources.ros1_helpers import write_rosbag

pytestmark = pytest.mark.slow
REPO = Path(__file__).resolve().parents[3]
IMAGES, IMAGE_BYTES = 60, 300_000


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@contextmanager
def server_on(port: int, command: list[str], name: str) -> Iterator[None]:
    """``command`` (a server on ``port`` of 127.0.0.1) running, once it accepts connections, for as long
    as the context lasts."""
    server = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 30
        while True:
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError:
                assert time.monotonic() < deadline and server.poll() is None, f"{name} did not start"
                time.sleep(0.2)
        yield
    finally:
        server.terminate()
        server.wait(timeout=10)


def tfx(*args: str, env: dict[str, str]) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "tftools", *args], cwd=REPO, env=env, capture_output=True, text=True, timeout=300
    )


@pytest.fixture(scope="module")
def s3_env() -> Iterator[dict[str, str]]:
    """A moto S3 server on a free port of 127.0.0.1, and the environment that points at it."""
    port = free_port()
    command = [sys.executable, "-c", "from moto.server import main; main()", "-H", "127.0.0.1", "-p", str(port)]
    with server_on(port, command, "moto's server"):
        yield {
            **os.environ,
            "AWS_ENDPOINT_URL": f"http://127.0.0.1:{port}",
            "AWS_ACCESS_KEY_ID": "testing",
            "AWS_SECRET_ACCESS_KEY": "testing",
            "AWS_DEFAULT_REGION": "us-east-1",
        }


@pytest.fixture(scope="module")
def fleet(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The local fleet: the sample bags, a corrupt bag and an uncompressed ROS1 image bag."""
    root = tmp_path_factory.mktemp("fleet")
    shutil.copy(SAMPLE_BAGS["ros1"], root / "robot.bag")
    shutil.copytree(SAMPLE_BAGS["db3"], root / "robot_db3")
    shutil.copytree(SAMPLE_BAGS["mcap"], root / "robot_mcap")
    (root / "corrupt.bag").write_bytes(b"#ROSBAG V2.0\n" + os.urandom(20_000))
    return root


@pytest.fixture(scope="module")
def bucket(s3_env: dict[str, str], fleet: Path) -> str:
    import s3fs

    fs = s3fs.S3FileSystem(client_kwargs={"endpoint_url": s3_env["AWS_ENDPOINT_URL"]}, key="testing", secret="testing")
    fs.mkdir("bucket")
    fs.put(str(fleet), "bucket/fleet", recursive=True)
    return "s3://bucket/fleet/"


def test_wtf_checks_every_recording_in_the_bucket_as_on_its_local_copy(
    rosbag_available: None,  # noqa: F811
    s3_env: dict[str, str],
    fleet: Path,
    bucket: str,
) -> None:
    import s3fs

    image_bag = write_rosbag(fleet / "images.bag", interleaved(IMAGES, IMAGE_BYTES), "none")
    fs = s3fs.S3FileSystem(client_kwargs={"endpoint_url": s3_env["AWS_ENDPOINT_URL"]}, key="testing", secret="testing")
    fs.put(str(image_bag), "bucket/fleet/images.bag")
    remote = tfx("wtf", bucket, "--format", "json", env=s3_env)
    local = tfx("wtf", f"{fleet}/", "--format", "json", env=s3_env)
    assert remote.returncode == local.returncode == 1, remote.stderr  # the corrupt bag fails the fleet
    got, expected = json.loads(remote.stdout), json.loads(local.stdout)
    names = [b["paths"][0].rsplit("/", 1)[-1] for b in got["bags"]]
    assert names == ["corrupt.bag", "images.bag", "robot.bag", "robot_db3", "robot_mcap"]
    assert names == [Path(b["paths"][0]).name for b in expected["bags"]]
    corrupt = got["bags"][0]
    assert corrupt["error"]["code"] == "unreadable"
    assert "s3://bucket/fleet/corrupt.bag: corrupt" in corrupt["error"]["message"]
    for mine, theirs in zip(got["bags"][1:], expected["bags"][1:], strict=True):
        assert mine["transforms"] == theirs["transforms"] and mine["frames"] == theirs["frames"]
        assert [f["message"] for f in mine["findings"]] == [f["message"] for f in theirs["findings"]]
    images = got["bags"][1]["fetched"][0]
    tf_bytes = image_bag.stat().st_size - IMAGES * IMAGE_BYTES  # transforms, headers and the index
    assert images["size"] == image_bag.stat().st_size
    assert images["received"] < 4 * tf_bytes + 256 * 1024 < 0.05 * images["size"]
    text = tfx("wtf", "s3://bucket/fleet/images.bag", env=s3_env)
    assert re.search(r"fetched [\d.]+ MB of [\d.]+ MB \(\d\.\d%\)", text.stdout), text.stdout


@pytest.mark.parametrize(
    ("url", "said"),
    [
        ("s3://bucket/fleet/missing.bag", "missing.bag: no such file or directory"),
        ("s3://no-such-bucket/run.bag", "no-such-bucket/run.bag: no such file or directory"),
    ],
)
def test_a_missing_object_or_bucket_is_one_line(s3_env: dict[str, str], bucket: str, url: str, said: str) -> None:
    done = tfx("frames", "-b", url, env=s3_env)
    assert done.returncode == 2 and said in done.stderr and len(done.stderr.strip().splitlines()) == 1, done.stderr
    done = tfx("wtf", url, env=s3_env)
    assert done.returncode == 2 and said in done.stderr and "Traceback" not in done.stderr


@pytest.mark.parametrize("name", ["robot.bag", "robot_mcap"])
def test_static_repair_copies_a_recording_from_the_bucket(
    s3_env: dict[str, str], fleet: Path, bucket: str, tmp_path: Path, name: str
) -> None:
    """A bag copier reads every byte: the recording is fetched whole, the copy written locally, as
    from the local file (the same transforms and statics)."""
    remote, local = tmp_path / "remote", tmp_path / "local"
    done = tfx("static", "--repair", "-b", bucket + name, "-o", str(remote), env=s3_env)
    assert done.returncode == 0, done.stderr
    assert f"a copy of {bucket}{name} whose /tf_static is durable, with its 7 static" in done.stdout
    assert tfx("static", "--repair", "-b", str(fleet / name), "-o", str(local), env=s3_env).returncode == 0
    checked = [
        json.loads(tfx("wtf", str(out), "--format", "json", env=s3_env).stdout)["bags"][0] for out in (remote, local)
    ]
    assert checked[0]["transforms"] == checked[1]["transforms"] > 6000 and checked[0]["findings"] == []


def test_a_url_without_the_extra_is_one_line_with_the_pip_command(tmp_path: Path) -> None:
    blocked = "import sys; sys.modules['fsspec'] = None; from tftools.cli.app import main; main()"
    done = subprocess.run(
        [sys.executable, "-c", blocked, "wtf", "s3://bucket/run.bag"], cwd=REPO, capture_output=True, text=True
    )
    assert done.returncode == 2
    said = "tfx: error: reading recordings by URL needs tftools[fleet]: pip install 'tftools[fleet]'"
    assert done.stderr.strip() == said


class _RangedHandler(http.server.SimpleHTTPRequestHandler):
    """http.server's files, with the ranged reads (``Range: bytes=a-b``) it lacks."""

    def do_GET(self) -> None:
        wanted = re.fullmatch(r"bytes=(\d+)-(\d+)", self.headers.get("Range", ""))
        path = Path(self.translate_path(self.path))
        if wanted is None or not path.is_file():
            super().do_GET()
            return
        data = path.read_bytes()
        start, end = int(wanted[1]), min(int(wanted[2]) + 1, len(data))
        self.send_response(206)
        self.send_header("Content-Range", f"bytes {start}-{end - 1}/{len(data)}")
        self.send_header("Content-Length", str(end - start))
        self.end_headers()
        self.wfile.write(data[start:end])

    def log_message(self, *args: object) -> None:
        pass


def test_http_recordings_are_read_with_ranged_reads(fleet: Path) -> None:
    handler = lambda *a: _RangedHandler(*a, directory=str(fleet))  # noqa: E731
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        base = f"http://127.0.0.1:{server.server_address[1]}"
        remote = tfx("frames", "-b", f"{base}/robot.bag", "--format", "json", env=dict(os.environ))
        local = tfx("frames", "-b", str(fleet / "robot.bag"), "--format", "json", env=dict(os.environ))
        assert remote.returncode == 0, remote.stderr
        assert json.loads(remote.stdout)["frames"] == json.loads(local.stdout)["frames"]
        missing = tfx("frames", "-b", f"{base}/nothing.bag", env=dict(os.environ))
        assert missing.returncode == 2 and "nothing.bag: no such file or directory" in missing.stderr
    finally:
        server.shutdown()


@pytest.mark.parametrize("name", ["robot.bag", "robot_db3", "robot_mcap"])
def test_a_replay_streams_from_the_bucket_as_from_its_local_copy(
    s3_env: dict[str, str], fleet: Path, bucket: str, name: str
) -> None:
    """``--play`` reads the recording window by window through the URL: the same refreshes as locally."""
    play = ("map", "gripper", "--play", "--rate", "1000", "--format", "json")
    remote = tfx("monitor", *play, "-b", f"{bucket}{name}", env=s3_env)
    local = tfx("monitor", *play, "-b", str(fleet / name), env=s3_env)
    assert remote.returncode == local.returncode == 0, remote.stderr
    last_remote, last_local = json.loads(remote.stdout.splitlines()[-1]), json.loads(local.stdout.splitlines()[-1])
    assert last_remote["edges"] == last_local["edges"] and last_remote["chain"] == last_local["chain"]
