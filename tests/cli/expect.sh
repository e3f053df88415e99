# Shared by the CLI test scripts (sourced): expect and ok count into the
# caller's pass and fail, and write into the caller's $tmp.
# expect CODE [NEEDLE] -- COMMAND...: exit code CODE and, if given, NEEDLE in stderr.
expect() {
  local want=$1 needle=$2; shift 3
  "$@" >"$tmp/out" 2>"$tmp/err"
  local got=$?
  if [[ $got -ne $want ]]; then
    echo "FAIL: exit $got, expected $want: $*"; sed 's/^/  /' "$tmp/err"; fail=$((fail+1)); return
  fi
  if [[ -n $needle ]] && ! grep -qF -- "$needle" "$tmp/err" "$tmp/out"; then
    echo "FAIL: no '$needle' in the output of: $*"; sed 's/^/  /' "$tmp/err"; fail=$((fail+1)); return
  fi
  pass=$((pass+1))
}
# ok CONDITION MESSAGE: CONDITION (evaluated) holds, else MESSAGE.
ok() { if eval "$1"; then pass=$((pass+1)); else echo "FAIL: $2"; fail=$((fail+1)); fi; }
