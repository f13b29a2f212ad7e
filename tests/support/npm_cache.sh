# Sourced by the tests that check the rig against an implementation from npm: installs packages
# into a cache outside the repository, once, so that nothing of them is kept in the tree.
#
# npm_cache_install CACHE PACKAGE@VERSION...: CACHE/node_modules holds the packages afterwards.
# Installs into a fresh folder first and moves it into place, so that an interrupted install
# leaves no half cache behind. Returns 0 when installed (or already there), 77 when node or npm
# is missing or npm cannot reach the registry (a machine without them, not a defect of the rig),
# 1 when npm failed otherwise; says why on standard output.
npm_cache_install() {
  local cache=$1 staging tool first_package=${2%@*}
  shift
  for tool in node npm; do
    command -v "$tool" >/dev/null || {
      echo "SKIP: no $tool (./scripts/setup test installs Node.js and npm)"
      return 77
    }
  done
  [[ -f $cache/node_modules/$first_package/package.json ]] && return 0
  mkdir -p "$(dirname "$cache")"
  echo "installing $* into $cache"
  staging=$(mktemp -d "$cache.XXXXXX")
  if ! npm install --prefix "$staging" --no-save --no-audit --no-fund --loglevel=error "$@" \
    >"$staging.log" 2>&1; then
    if grep -qE 'ENOTFOUND|EAI_AGAIN|ECONNREFUSED|ECONNRESET|ETIMEDOUT|ENETUNREACH' \
      "$staging.log"; then
      echo "SKIP: npm cannot reach the registry:"
      cat "$staging.log"
      rm -rf "$staging" "$staging.log"
      return 77
    fi
    echo "FAIL: npm could not install $*:"
    cat "$staging.log"
    rm -rf "$staging" "$staging.log"
    return 1
  fi
  rm -rf "$cache" "$staging.log"
  mv "$staging" "$cache"
}
