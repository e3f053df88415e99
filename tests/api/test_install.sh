#!/usr/bin/env bash
# relief as an installed library: `cmake --install` into a staging prefix,
# then
#  - the shared library exports only relief_* functions, each declared in
#    an installed header;
#  - a program outside the tree, built from the installed header and
#    `pkg-config --cflags --libs relief`, completes a mesh, fills an image
#    and repairs a depth image;
#  - the same program built by CMake with find_package(relief CONFIG).
#   test_install.sh BUILD_DIR SOURCE_DIR
set -u
build=$1 src=$2
tmp=$(mktemp -d /tmp/relief-install-XXXXXX)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
ok() { if eval "$1"; then pass=$((pass + 1)); else echo "FAIL: $2"; fail=$((fail + 1)); fi; }
stage=$tmp/stage

cmake --install "$build" --prefix "$stage" > "$tmp/install.log" 2>&1 ||
  { cat "$tmp/install.log"; echo "FAIL: cmake --install"; exit 1; }
libdir=$(dirname "$(find "$stage" -name librelief.so | head -1)")
ok '[[ -f $stage/include/relief/relief.h && -f $stage/include/relief/image.h ]]' "headers not installed"
ok '[[ -L $libdir/librelief.so && -f $libdir/librelief.a && -f $libdir/pkgconfig/relief.pc ]]' "libraries or relief.pc not installed"
ok '[[ -x $stage/bin/relief ]]' "the program not installed"
ok '[[ -s $stage/share/man/man1/relief.1 ]]' "the manual page relief(1) not installed"
# The GIMP plug-in, where it is built: under the prefix, never outside it.
if [[ -x $build/plugins/gimp/relief-heal-selection ]]; then
  ok '[[ -n $(find "$stage" -path "*/plug-ins/relief-heal-selection/relief-heal-selection") ]]' "the GIMP plug-in is not installed under the prefix"
  ok '! grep -q "Installing: /usr/lib/gimp" "$tmp/install.log"' "cmake --install wrote the GIMP plug-in outside the prefix"
fi
ok 'objdump -p "$libdir/librelief.so" | grep -q "SONAME *librelief.so.0"' "SONAME is not librelief.so.0"

# Every installed header stands alone, in C11 (pedantic) and in C++.
for h in "$stage"/include/relief/*.h; do
  printf '#include <relief/%s>\nint main(void) { return 0; }\n' "$(basename "$h")" > "$tmp/h.c"
  ok 'cc -std=c11 -pedantic -Wall -Wextra -Werror -I"$stage/include" -c "$tmp/h.c" -o "$tmp/h.o" 2>"$tmp/h.log"' "$(basename "$h") does not compile alone as C: $(head -3 "$tmp/h.log")"
  ok 'c++ -x c++ -Wall -Wextra -Werror -I"$stage/include" -c "$tmp/h.c" -o "$tmp/h.o" 2>"$tmp/h.log"' "$(basename "$h") does not compile alone as C++: $(head -3 "$tmp/h.log")"
done

# Exports: relief_* only, and every one declared in an installed header.
nm -D --defined-only "$libdir/librelief.so" | awk '$2 ~ /^[TDBRVW]$/ {print $3}' | sed 's/@.*//' | sort -u > "$tmp/exports"
ok '[[ -s $tmp/exports ]]' "no exports"
ok '! grep -v "^relief_" "$tmp/exports"' "exports other than relief_*: $(grep -v '^relief_' "$tmp/exports" | head -5 | tr '\n' ' ')"
missing=""
while read -r sym; do
  grep -qw "$sym" "$stage"/include/relief/*.h || missing+=" $sym"
done < "$tmp/exports"
ok '[[ -z $missing ]]' "exported but in no installed header:$missing"
ok 'grep -qw relief_image_fill "$tmp/exports" && grep -qw relief_complete "$tmp/exports"' "engines not exported"

# pkg-config.
export PKG_CONFIG_PATH=$libdir/pkgconfig
flags=$(pkg-config --cflags --libs relief 2>&1)
ok '[[ $? -eq 0 && $flags == *-lrelief* ]]' "pkg-config --libs relief: $flags"
cc -std=c11 -Wall -Wextra -o "$tmp/consumer_pc" "$src/tests/api/consumer/consumer.c" $flags -lm \
   -Wl,-rpath,"$libdir" > "$tmp/cc.log" 2>&1
ok '[[ -x $tmp/consumer_pc ]]' "the pkg-config consumer does not build: $(head -5 "$tmp/cc.log")"
if [[ -x $tmp/consumer_pc ]]; then
  "$tmp/consumer_pc" > "$tmp/pc.out" 2>&1
  ok '[[ $? -eq 0 ]]' "the pkg-config consumer failed: $(cat "$tmp/pc.out")"
  ok 'ldd "$tmp/consumer_pc" | grep -q "$libdir/librelief.so.0"' "the consumer does not load the staged librelief.so.0"
fi

# CMake package.
cmake -S "$src/tests/api/consumer" -B "$tmp/cm" -DCMAKE_PREFIX_PATH="$stage" \
      -DCMAKE_BUILD_RPATH="$libdir" > "$tmp/cm.log" 2>&1 &&
  cmake --build "$tmp/cm" >> "$tmp/cm.log" 2>&1
ok '[[ -x $tmp/cm/consumer ]]' "the find_package consumer does not build: $(tail -5 "$tmp/cm.log")"
if [[ -x $tmp/cm/consumer ]]; then
  "$tmp/cm/consumer" > "$tmp/cm.out" 2>&1
  ok '[[ $? -eq 0 ]]' "the find_package consumer failed: $(cat "$tmp/cm.out")"
fi

echo "test_install: $pass passed, $fail failed"
[[ $fail -eq 0 ]]
