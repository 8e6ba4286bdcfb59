#!/usr/bin/env bash
# Screenshots the verification page (results/verify/index.html, or the page given) with headless
# Chromium, for review of how the figures and the table look in a browser; not run in CI.
#
# usage: scripts/screenshot-index.sh [PAGE] [OUT.png] [--height PIXELS]
# Needs Debian's `chromium` package (apt-get install chromium). The page is opened from disk,
# as a reader without network access opens it.
set -euo pipefail
cd "$(dirname "$0")/.."
page=results/verify/index.html
out=results/verify/index.png
height=6000
positional=()
while [ $# -gt 0 ]; do
    case "$1" in
        --height) height="$2"; shift 2 ;;
        *) positional+=("$1"); shift ;;
    esac
done
[ ${#positional[@]} -ge 1 ] && page="${positional[0]}"
[ ${#positional[@]} -ge 2 ] && out="${positional[1]}"
if [ ! -f "$page" ]; then
    echo "no page at $page: run 'cargo run --release -- verify' first" >&2
    exit 2
fi
browser=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$browser" ]; then
    echo "headless Chromium not found: apt-get install chromium" >&2
    exit 2
fi
"$browser" --headless --no-sandbox --disable-gpu --hide-scrollbars \
    --window-size=1400,"$height" --screenshot="$(realpath -m "$out")" \
    "file://$(realpath "$page")" 2>/dev/null
echo "wrote $out"
