# Sourced by the benches that compare with OpenCV (image_fill.sh,
# depth_fill.sh): sets PY to Debian's python (where python3-opencv goes,
# not a pyenv or venv in PATH; $PYTHON overrides) and installs
# python3-opencv (as root) when it is missing. OpenCV is a peer to compare
# with, never linked.
PY=${PYTHON:-/usr/bin/python3}
[[ -x $PY ]] || PY=python3
if ! "$PY" -c 'import cv2, numpy' 2>/dev/null; then
  if [[ $(id -u) -ne 0 ]]; then
    echo "bench: python3-opencv is missing (apt-get install python3-opencv)" >&2
    exit 1
  fi
  echo "bench: installing python3-opencv to compare with"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    python3-opencv python3-numpy >/dev/null
fi
