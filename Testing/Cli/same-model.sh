#!/usr/bin/env bash
# same-model.sh CLI DIR NAME 'OPTIONS A' 'OPTIONS B' [differ]: runs `reconstruct` in DIR with each set of options
# (on the CPU) and compares the two models byte for byte: equal passes; with `differ`, different passes (the control
# that shows the comparison can fail).
set -uo pipefail
cli=$1 dir=$2 name=$3 a=$4 b=$5 expect=${6:-same}
cd "$dir" || exit 1
# shellcheck disable=SC2086 # the options are words
"$cli" reconstruct $a --device cpu --quiet --out "$name-a.ply" || { echo "FAIL: reconstruct $a"; exit 1; }
# shellcheck disable=SC2086
"$cli" reconstruct $b --device cpu --quiet --out "$name-b.ply" || { echo "FAIL: reconstruct $b"; exit 1; }
if cmp -s "$name-a.ply" "$name-b.ply"; then
  [ "$expect" = same ] && { echo "same model: $a | $b"; exit 0; }
  echo "FAIL: the models are the same, expected them to differ: $a | $b"; exit 1
fi
[ "$expect" = differ ] && { echo "the models differ, as expected: $a | $b"; exit 0; }
echo "FAIL: the models differ: $a | $b"; exit 1
