#!/usr/bin/env bash
# One-command set-up on a fresh Debian machine (as root):
#   ./setup.sh          install what is missing, build, run the demo completion
#   ./setup.sh deps     install what is missing, nothing else
#   ./setup.sh build    install what is missing and build
#   ./setup.sh python   install what is missing and build the Python package
#                       into .venv (the full set-up does this too)
# Idempotent: packages already there are not reinstalled, the build is
# incremental. Environment: BUILD_DIR (default build), JOBS (default nproc).
set -euo pipefail
cd "$(dirname "$0")"

# locales: localedef's sources, for the tests' comma-decimal locale
# (tests/comma_locale.sh).
PACKAGES=(cmake make gcc g++ pkg-config
          libopenmesh-dev libflann-dev libqhull-dev zlib1g-dev libpng-dev libjpeg-dev liblzf-dev
          ocl-icd-opencl-dev opencl-headers pocl-opencl-icd clinfo
          clang libclang-rt-dev valgrind
          python3 python3-venv python3-dev ninja-build man-db
          gimp libgimp2.0-dev python3-open3d
          locales)
# The Python package's build and test tools, from PyPI into .venv.
# dask runs the batch recipe; trimesh, OpenCV and scikit-image, the interop
# tests (tests/python/test_interop.py).
PY_PACKAGES=(nanobind scikit-build-core "numpy>=2" pytest "dask[distributed]"
             trimesh opencv-python-headless scikit-image)
BUILD_DIR=${BUILD_DIR:-build}
JOBS=${JOBS:-$(nproc)}

install_deps() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [[ ${#missing[@]} -eq 0 ]] && return 0
  if [[ $(id -u) -ne 0 ]]; then
    echo "setup: missing packages: ${missing[*]}; run this as root (or: sudo apt-get install ${missing[*]})" >&2
    exit 1
  fi
  echo "setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

build() {
  cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" >/dev/null
  cmake --build "$BUILD_DIR" -j"$JOBS"
}

# The Python package (python/) built over the library and installed into
# the project's virtual environment .venv: afterwards
# `.venv/bin/python -c "import relief"` works. Its build folder is
# build/python, kept between runs. The venv is Debian's Python's
# (PYTHON), with its system packages in view: Open3D comes from Debian
# (python3-open3d, for the interop test), built for that Python; the rest
# from PyPI, inside the venv.
PYTHON=${PYTHON:-/usr/bin/python3}
python_package() {
  [[ -x .venv/bin/python ]] || "$PYTHON" -m venv --system-site-packages .venv
  .venv/bin/python -m pip install -q --disable-pip-version-check "${PY_PACKAGES[@]}"
  .venv/bin/python -m pip install -q --disable-pip-version-check --no-build-isolation ./python
  echo "setup: Python package relief $(.venv/bin/python -c 'import relief; print(relief.__version__)') in .venv"
}

demo() {
  local out=out/demo relief=$BUILD_DIR/relief
  mkdir -p "$out"
  "$relief" synth cylinder-bark --colour --seed 1 -o "$out/capture.ply" --truth "$out/truth.ply"
  echo "setup: demo input: $out/capture.ply (a 2.5D capture of a bark-textured cylinder; truth in $out/truth.ply)"
  set +e
  "$relief" complete "$out/capture.ply" -o "$out/completed.ply" --report "$out/report.json" \
    --report-dir "$out/report" \
    2> >(tee "$out/complete.log" >&2)
  local rc=$?
  set -e
  wait
  [[ $rc -eq 0 ]] || exit $rc
  echo "setup: completed mesh: $out/completed.ply"
  echo "setup: report:         $out/report.json"
  echo "setup: pictures:       $(pwd)/$out/report/index.html (open it in a browser)"
}

case "${1:-all}" in
  deps) install_deps ;;
  build) install_deps; build ;;
  python) install_deps; python_package ;;
  all) install_deps; build; python_package; demo ;;
  *) echo "usage: $0 [deps|build|python]" >&2; exit 1 ;;
esac
