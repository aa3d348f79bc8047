#!/usr/bin/env bash
# Browser test of the HTML reports (issue 17): every index.html under OUT
# opened in Debian's headless Chromium (tests/browser/check.mjs says what is
# checked). Without OUT it runs `mre demo` into a temporary folder first.
# Screenshots go to $SCREENSHOTS (default target/browser-screenshots).
# Needs: chromium (Debian package) and node >= 20.10.
# Usage: tests/browser/check.sh [OUT]
set -euo pipefail
cd "$(dirname "$0")/../.."
command -v chromium >/dev/null || { echo "needs Debian's chromium: apt-get install -y chromium"; exit 1; }
# check.mjs speaks the DevTools protocol over Node's built-in WebSocket (Node >= 20.10).
node -e 'const [a, b] = process.versions.node.split(".").map(Number); process.exit(a > 20 || (a === 20 && b >= 10) ? 0 : 1)' \
  || { echo "needs node >= 20.10 (has $(node --version 2>/dev/null || echo none))"; exit 1; }
shots=${SCREENSHOTS:-target/browser-screenshots}
if [ $# -ge 1 ]; then
  out=$1
else
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  out=$tmp/out
  cargo run -q -p host-tools -- demo --out "$out" > "$tmp/demo.log"
  # The demo's last line is the one page to open.
  last=$(tail -n 1 "$tmp/demo.log")
  [ "$last" = "$out/index.html" ] || { echo "demo did not end with $out/index.html: $last"; exit 1; }
fi
mapfile -t pages < <(find "$out" -name index.html | sort)
[ ${#pages[@]} -gt 0 ] || { echo "no index.html under $out"; exit 1; }
rm -rf "$shots"
node --experimental-websocket --no-warnings tests/browser/check.mjs "$shots" "${pages[@]}"
