# Sourced by the benches that compare with a peer run from Python
# (image_fill.sh and depth_fill.sh: OpenCV; points.sh: Open3D): sets PY to
# Debian's python (where the python3-* packages go, not a pyenv or venv in
# PATH; $PYTHON overrides) and installs the peer's package (as root) when
# its module is missing. Peers are compared with, never linked.
#   PEER_MODULE  the module to import (default cv2)
#   PEER_PACKAGE its Debian package (default python3-opencv)
PY=${PYTHON:-/usr/bin/python3}
[[ -x $PY ]] || PY=python3
PEER_MODULE=${PEER_MODULE:-cv2}
PEER_PACKAGE=${PEER_PACKAGE:-python3-opencv}
if ! "$PY" -c "import $PEER_MODULE, numpy" 2>/dev/null; then
  if [[ $(id -u) -ne 0 ]]; then
    echo "bench: $PEER_PACKAGE is missing (apt-get install $PEER_PACKAGE)" >&2
    exit 1
  fi
  echo "bench: installing $PEER_PACKAGE to compare with"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    "$PEER_PACKAGE" python3-numpy >/dev/null
fi
