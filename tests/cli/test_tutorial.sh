#!/usr/bin/env bash
# docs/tutorial.md as written: its files (```json file=NAME, ```python file=NAME) are written and
# its ```sh blocks run in order, in one shell, in a temporary folder, with the program under test
# first on PATH and Debian's python3 first; every command must succeed (a command expected to fail
# says so itself, `|| echo ...`), and the outputs each step names must exist.
# Usage: test_tutorial.sh HARNESS SOURCE_DIR
set -u
H="$1"; SRC="$2"
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
mkdir -p "$T/bin"
ln -s "$(readlink -f "$H")" "$T/bin/harness"
ln -s "${PYTHON:-/usr/bin/python3}" "$T/bin/python3"
# The script: files first where they appear, then commands; the tutorial's own `cd` and PATH lines
# are kept but pointed at this test's folder and program.
"${PYTHON:-/usr/bin/python3}" - "$SRC/docs/tutorial.md" "$T/script.sh" "$T" <<'PY' || { echo "FAIL: cannot read the tutorial"; exit 1; }
import re, shlex, sys
text = open(sys.argv[1]).read()
out, tmp = [], sys.argv[3]
for info, body in re.findall(r"```([^\n]*)\n(.*?)```", text, re.S):
    info = info.strip()
    m = re.match(r"(\w+) file=(\S+)$", info)
    if m:
        out.append("cat > %s <<'TUTORIAL_EOF'\n%sTUTORIAL_EOF" % (shlex.quote(m.group(2)), body))
    elif info == "sh":
        body = body.replace("/tmp/my_study", tmp + "/study")
        body = body.replace("export REPO=$PWD PATH=$PWD/build/bin:$PATH", "export REPO=__SRC__ PATH=%s/bin:$PATH" % tmp)
        out.append(body)
if len(out) < 8:
    sys.exit("the tutorial has %d blocks" % len(out))
open(sys.argv[2], "w").write("set -e\n" + "\n".join(out) + "\n")
PY
sed -i "s|__SRC__|$SRC|" "$T/script.sh"
fail=0
( cd "$SRC" && bash "$T/script.sh" ) > "$T/log" 2>&1 || { echo "FAIL: the tutorial's commands"; tail -30 "$T/log"; fail=1; }
S="$T/study"
for f in out/run/summary.json out/ref/summary.json out/exact/summary.json out/sweep/runs.csv out/sweep/no_force/summary.json \
         out/card/card.md out/card/card.png out/card/card.csv out/error_time.png out/studies/accuracy_time.csv out/studies/ablation.csv; do
  [[ -s "$S/$f" ]] || { echo "FAIL: the tutorial made no $f"; fail=1; }
done
grep -q "harness: error: my_press.json: contacts.0.force: value -1 out of range" "$T/log" || { echo "FAIL: the error line shown"; fail=1; }
grep -q "^exit 2$" "$T/log" || { echo "FAIL: the bad run's exit status 2"; fail=1; }
[[ ! -e "$S/out/bad" ]] || { echo "FAIL: the bad run wrote out/bad"; fail=1; }
grep -q "^| voxel_exact |" "$S/out/card/card.md" && grep -q "^| no contact force |" "$S/out/card/card.md" \
  || { echo "FAIL: the card's rows"; fail=1; }
[[ $fail -eq 0 ]] && echo "the tutorial ran: $(grep -c . "$T/script.sh") lines"
exit $fail
