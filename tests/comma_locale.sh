#!/usr/bin/env bash
# Runs a command in a comma-decimal locale (de_DE.UTF-8: a half is "0,5"), as a
# GTK host such as GIMP, or Python after locale.setlocale, may call relief
# (issue 60: the API and Python tests run once so). The locale is made with
# localedef into LOCALE_DIR, once, and kept there for the next run. The command
# sees LOCPATH=LOCALE_DIR and RELIEF_TEST_LOCALE=de_DE.UTF-8 and sets that
# locale itself (tests/api/api_test.h, tests/python/conftest.py): a locale
# lives in the program, not in its environment.
#   tests/comma_locale.sh LOCALE_DIR COMMAND [ARGS...]
# Skipped (77) without localedef; an error when localedef cannot make the
# locale (its sources are Debian's locales package, which setup.sh installs).
set -euo pipefail
dir=$1
shift
name=de_DE.UTF-8
if [[ ! -e $dir/$name/LC_NUMERIC ]]; then
  if ! command -v localedef >/dev/null; then
    echo "comma_locale: no localedef (glibc's libc-bin); skipped"
    exit 77
  fi
  mkdir -p "$dir"
  # Made aside and renamed, so that two tests starting at once each see a
  # whole locale (the loser's rename fails and its copy is dropped).
  tmp=$(mktemp -d "$dir/.making-XXXXXX")
  if ! localedef -i de_DE -f UTF-8 "$tmp/$name" > "$tmp/log" 2>&1; then
    cat "$tmp/log" >&2
    rm -rf "$tmp"
    echo "comma_locale: localedef could not make $name (is the locales package installed? setup.sh installs it)" >&2
    exit 1
  fi
  mv -T "$tmp/$name" "$dir/$name" 2>/dev/null || true
  rm -rf "$tmp"
fi
export LOCPATH=$dir RELIEF_TEST_LOCALE=$name
exec "$@"
