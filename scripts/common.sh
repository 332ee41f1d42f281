# Shared by scripts/demo and scripts/test: configure and build in $IDTO_BUILD_DIR (default build/).
IDTO_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
IDTO_BUILD_DIR="${IDTO_BUILD_DIR:-$IDTO_ROOT/build}"
IDTO_JOBS="${IDTO_JOBS:-$(nproc 2>/dev/null || echo 2)}"

idto_build() {
  "$IDTO_ROOT/scripts/setup-deps"
  local extra=()
  if [ "${CI:-}" = "true" ]; then
    # CI runs everything: MuJoCo (plants, oracles), the Python module and chromium (the browser
    # tests) are required there, so that a missing one fails the run instead of skipping tests.
    extra+=(-DIDTO_WERROR=ON -DIDTO_WITH_MUJOCO=ON -DIDTO_BUILD_PYTHON=ON)
    export IDTO_REQUIRE_OPTIONAL_DEPS=1
  fi
  cmake -S "$IDTO_ROOT" -B "$IDTO_BUILD_DIR" -DCMAKE_BUILD_TYPE="${IDTO_BUILD_TYPE:-Release}" \
    "${extra[@]}" "$@"
  cmake --build "$IDTO_BUILD_DIR" -j "$IDTO_JOBS"
}
