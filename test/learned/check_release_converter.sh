#!/bin/sh
# scripts/convert_imo_release_checkpoint.py on the committed tiny release-architecture
# checkpoint must reproduce the committed .tcn, and a wrong file must give exit 2, one
# "error: <file>:0: ..." line and no output file. Usage: check_release_converter.sh <python3> <source dir>
set -u
PY=$1; SRC=$2; D=$SRC/test/learned/data; T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
"$PY" "$SRC/scripts/convert_imo_release_checkpoint.py" "$D/imo_release_tiny.pt" "$T/tiny.tcn" --window 10 --encoding text \
  || { echo "converter failed on the fixture"; exit 1; }
cmp "$T/tiny.tcn" "$D/imo_release_tiny.tcn" || { echo "converted fixture differs from the committed .tcn"; exit 1; }
for bad in "$D/imo_release_tiny_reference.txt" "$D/tcn_parity_reference.txt.missing"; do
  "$PY" "$SRC/scripts/convert_imo_release_checkpoint.py" "$bad" "$T/bad.tcn" 2>"$T/err"; rc=$?
  [ $rc -eq 2 ] || { echo "exit $rc on $bad, expected 2"; exit 1; }
  grep -q "^error: $bad:0: " "$T/err" || { echo "no error line for $bad:"; cat "$T/err"; exit 1; }
  [ $(wc -l < "$T/err") -eq 1 ] || { echo "more than one line on stderr"; exit 1; }
  [ ! -e "$T/bad.tcn" ] || { echo "wrote output for $bad"; exit 1; }
done
echo ok
