"""The package's writers on a full disk (issue 60 item 1, docs/limits.md):
write_mesh (every format), write_image (PNG of 8 and 16 bits, JPEG) and
write_depth (PFM, 16-bit PNG) over an older file with no room for the new
one raise ReliefError with status "system", naming the path and the
system's reason, and leave the older file byte for byte (size, mtime,
inode) with no temporary beside it.

The full disk is a small tmpfs mounted here when the tests run as root (as
CI does), filled but for a few KiB; otherwise a file size limit
(RLIMIT_FSIZE, SIGXFSZ ignored so that write() fails with EFBIG) on the
process that writes. Each write runs in a child process, which reports what
it raised: the limit never touches pytest's own files. DISK_FULL=rlimit
takes the limit even as root; skipped when neither way works.
"""
import hashlib
import json
import os
import shutil
import subprocess
import sys

import pytest

MOUNT_SIZE = 1 << 20

# The child: build the data, set the limit (if any) only then (after the
# imports, which may write bytecode), call the writer, print what it raised.
CHILD = r"""
import json, resource, signal, sys
import numpy as np, relief
kind, path, limit = sys.argv[1], sys.argv[2], int(sys.argv[3])
rng = np.random.default_rng(1)
n = 48
y, x = np.mgrid[0:n, 0:n].astype(np.float64)
v = np.stack([x, y, np.sin(x / 3) * np.cos(y / 5)], -1).reshape(-1, 3)
i = np.arange(n * n).reshape(n, n)[:-1, :-1].ravel()
f = np.concatenate([np.stack([i, i + 1, i + n], 1), np.stack([i + 1, i + n + 1, i + n], 1)])
if kind.startswith("mesh"):
    call = lambda: relief.write_mesh(path, v, f, colours=rng.random((len(v), 3)),
                                     labels=(x.ravel() > n / 2), ascii=kind == "mesh-ascii")
elif kind == "image8":
    call = lambda: relief.write_image(path, rng.integers(0, 255, (64, 64, 3), dtype=np.uint8))
elif kind == "image16":
    call = lambda: relief.write_image(path, rng.integers(0, 65535, (64, 64), dtype=np.uint16))
else:  # depth-pfm, depth-png16
    z = (1 + rng.random((64, 64))).astype(np.float32)
    call = lambda: relief.write_depth(path, z, format=kind[len("depth-"):])
if limit >= 0:
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (limit, resource.getrlimit(resource.RLIMIT_FSIZE)[1]))
try:
    call()
    print(json.dumps({"raised": None}))
except relief.ReliefError as e:
    print(json.dumps({"raised": "ReliefError", "status": e.status, "message": str(e)}))
except Exception as e:
    print(json.dumps({"raised": type(e).__name__, "message": str(e)}))
"""

# (kind, file name, bytes left free): a mesh is written partly before the
# disk is full (as the 102 400 of 104 332 bytes); the others at once.
CASES = [
    ("mesh", "m.ply", 8192), ("mesh-ascii", "m.ply", 8192), ("mesh", "m.obj", 8192),
    ("mesh", "m.off", 8192), ("mesh", "m.stl", 8192),
    ("image8", "i.png", 0), ("image8", "i.jpg", 0), ("image16", "i.png", 0),
    ("depth-pfm", "d.pfm", 0), ("depth-png16", "d.png", 0),
]


def _tmpfs_usable():
    return os.environ.get("DISK_FULL") != "rlimit" and os.geteuid() == 0 and shutil.which("mount")


def _rlimit_usable(tmp):
    probe = os.path.join(tmp, "probe")
    code = ("import resource, signal\n"
            "signal.signal(signal.SIGXFSZ, signal.SIG_IGN)\n"
            "resource.setrlimit(resource.RLIMIT_FSIZE, (1024, resource.RLIM_INFINITY))\n"
            f"f = open({probe!r}, 'wb', buffering=0)\n"
            "while True: f.write(bytes(4096))\n")  # a short write, then EFBIG
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    return r.returncode != 0 and "File too large" in r.stderr


@pytest.fixture(scope="module")
def disk(tmp_path_factory):
    """(mode, folder, reason): a folder on a full disk's file system."""
    top = tmp_path_factory.mktemp("disk_full")
    full = top / "full"
    full.mkdir()
    if _tmpfs_usable() and subprocess.run(
            ["mount", "-t", "tmpfs", "-o", f"size={MOUNT_SIZE},mode=0755", "tmpfs", str(full)],
            capture_output=True).returncode == 0:
        try:
            yield "tmpfs", full, "No space left on device"
        finally:
            subprocess.run(["umount", str(full)], capture_output=True)
        return
    if not _rlimit_usable(str(top)):
        pytest.skip("neither a tmpfs (needs root) nor a file size limit (RLIMIT_FSIZE)")
    yield "rlimit", full, "File too large"


def _state(path):
    st = os.stat(path)
    with open(path, "rb") as f:
        return hashlib.md5(f.read()).hexdigest(), st.st_size, st.st_mtime_ns, st.st_ino


def _fill(folder, free):
    """Fill folder's file system but for `free` bytes."""
    st = os.statvfs(folder)
    left = st.f_bavail * st.f_frsize - free
    with open(folder / "filler", "wb") as f:
        while left > 0:
            try:
                left -= f.write(bytes(min(left, 1 << 16)))
            except OSError:
                break


@pytest.mark.parametrize("kind,name,free", CASES,
                         ids=[f"{k}-{n}" for k, n, _ in CASES])
def test_full_disk(disk, kind, name, free):
    mode, folder, reason = disk
    for entry in os.listdir(folder):
        os.unlink(folder / entry)
    target = folder / name
    target.write_bytes(b"the user's older file\n")
    os.utime(target, ns=(981173106_000_000_000, 981173106_000_000_000))
    limit = -1
    if mode == "tmpfs":
        _fill(folder, free)
    else:
        limit = free
    before = _state(target)
    r = subprocess.run([sys.executable, "-c", CHILD, kind, str(target), str(limit)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    got = json.loads(r.stdout.strip().splitlines()[-1])
    assert got["raised"] == "ReliefError", f"{kind} {name}: {got}"
    assert got["status"] == "system", got
    assert str(target) in got["message"] and reason in got["message"], got["message"]
    assert ".relief-" not in got["message"], got["message"]
    assert _state(target) == before, f"{kind} {name}: the older file changed"
    left = [e for e in os.listdir(folder) if e.startswith(".relief-")]
    assert not left, f"temporaries left: {left}"
