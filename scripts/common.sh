# Shared by scripts/demo and scripts/test: configure and build in $IDTO_BUILD_DIR (default build/).
IDTO_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
IDTO_BUILD_DIR="${IDTO_BUILD_DIR:-$IDTO_ROOT/build}"
IDTO_JOBS="${IDTO_JOBS:-$(nproc 2>/dev/null || echo 2)}"

idto_build() {
  "$IDTO_ROOT/scripts/setup-deps"
  local extra=()
  [ "${CI:-}" = "true" ] && extra+=(-DIDTO_WERROR=ON)
  cmake -S "$IDTO_ROOT" -B "$IDTO_BUILD_DIR" -DCMAKE_BUILD_TYPE="${IDTO_BUILD_TYPE:-Release}" \
    "${extra[@]}" "$@"
  cmake --build "$IDTO_BUILD_DIR" -j "$IDTO_JOBS"
}
