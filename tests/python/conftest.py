"""The Python tests' shared set-up: a comma-decimal locale (issue 60).

Under tests/comma_locale.sh (ctest's test_python_comma) RELIEF_TEST_LOCALE
names a comma-decimal locale made there, and the whole suite runs in it, as
relief runs in a program that called locale.setlocale: set here, before any
test. The fixture ``comma_locale`` gives one test that locale in any run,
made with localedef when the script did not make it.
"""
import locale
import os
import shutil
import subprocess

import pytest

LOCALE = "de_DE.UTF-8"


def _set_comma(name):
    locale.setlocale(locale.LC_ALL, name)
    point = locale.localeconv()["decimal_point"]
    assert point == ",", f"the locale {name} writes {point!r} as its decimal point, not ','"


if os.environ.get("RELIEF_TEST_LOCALE"):
    _set_comma(os.environ["RELIEF_TEST_LOCALE"])


def _made(tmp_path_factory, name):
    """A folder holding the locale `name`, made there with localedef once a
    run."""
    made = tmp_path_factory.getbasetemp() / "locale"
    if not (made / name / "LC_NUMERIC").exists():
        localedef = shutil.which("localedef")
        if not localedef:
            pytest.skip("no localedef to make a comma-decimal locale")
        made.mkdir(exist_ok=True)
        r = subprocess.run([localedef, "-i", "de_DE", "-f", "UTF-8", str(made / name)],
                           capture_output=True, text=True)
        assert r.returncode == 0, f"localedef (the locales package?): {r.stderr}"
    return made


@pytest.fixture
def comma_locale(tmp_path_factory):
    """The program's locale a comma-decimal one for the test, put back after;
    skipped without localedef."""
    name = os.environ.get("RELIEF_TEST_LOCALE")
    saved = locale.setlocale(locale.LC_ALL)
    try:
        if name:
            _set_comma(name)
        else:
            # glibc reads LOCPATH when setlocale loads a locale, only then:
            # the rest of the run keeps its own.
            name, before = LOCALE, os.environ.get("LOCPATH")
            os.environ["LOCPATH"] = str(_made(tmp_path_factory, LOCALE))
            try:
                _set_comma(name)
            finally:
                if before is None:
                    del os.environ["LOCPATH"]
                else:
                    os.environ["LOCPATH"] = before
        yield name
    finally:
        locale.setlocale(locale.LC_ALL, saved)
