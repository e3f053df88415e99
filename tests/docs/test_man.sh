#!/usr/bin/env bash
# relief(1) (issue 44): the page the build writes (relief --man) renders with
# man -l and groff without a warning, has a section for every command that
# `relief --help` lists, and each section names every option the command's
# --help shows (both come from the command's spec: this catches a command
# or an option the generator leaves out).
#   test_man.sh RELIEF BUILD_DIR
set -u
relief=$1 build=$2
page=$build/relief.1
fail=0
[[ -s $page ]] || { echo "FAIL: $page missing: the build writes it (target relief_man)"; exit 1; }
command -v man >/dev/null || { echo "man not installed: skipped"; exit 77; }
cmp -s "$page" <("$relief" --man) || { echo "FAIL: $page differs from relief --man"; fail=1; }
warn=$(groff -man -ww -z "$page" 2>&1)
[[ -z $warn ]] || { echo "FAIL: groff warns: $warn"; fail=1; }
text=$(MANWIDTH=100 man -l "$page" 2>&1) || { echo "FAIL: man -l $page"; fail=1; }
cmds=$("$relief" --help | awk '/^commands:/ { on = 1; next } on && /^  [a-z]/ { print $1 } /^$/ && on { exit }')
n=0
for c in $cmds; do
  n=$((n + 1))
  grep -q "^   relief $c\$" <<<"$text" || { echo "FAIL: no section for relief $c"; fail=1; continue; }
  section=$(awk -v c="relief $c" '$0 == "   " c { on = 1; next } /^   relief / { on = 0 } on' <<<"$text")
  for opt in $("$relief" "$c" --help | grep -oE '^  (-o, )?--[a-z][a-z0-9-]*' | grep -oE -- '--[a-z0-9-]+'); do
    grep -qF -- "$opt" <<<"$section" || { echo "FAIL: relief $c: $opt in --help, not in relief(1)"; fail=1; }
  done
done
[[ $n -ge 13 ]] || { echo "FAIL: only $n commands listed by relief --help"; fail=1; }
[[ $fail -eq 0 ]] && echo "relief(1): $n commands, every option of their --help, renders cleanly"
exit $fail
