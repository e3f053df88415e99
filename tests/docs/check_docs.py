#!/usr/bin/env python3
"""The documentation against the code (issue 44), for README.md and docs/*.md:

- every relative link and picture resolves (a file, and a heading for a
  #anchor);
- every command `relief --help` lists has a page with its option table,
  and each table between <!-- options: CMD --> and <!-- end options -->
  is what `relief CMD --help-markdown` prints (the table --help and the
  manual page come from: one source);
- docs/c-api.md's function index is the headers' RELIEF_API functions;
- docs/usage.md's synopsis is the commands' own first --help lines;
- each page's report table (<!-- report: FILE -->) lists the members of
  the report its example wrote (default pass);
- every fenced block marked as an example (```sh example, ```python
  example) runs, in order per file, in a scratch folder where build/, docs/
  and ../shared/ are the repository's (python ones with the project's
  .venv, skipped when it cannot import relief). RELIEF_TEST_PASS=sanitize
  skips the examples (the default pass runs them).

  check_docs.py SOURCE_DIR RELIEF [--update]   (--update rewrites the tables)
"""
import json
import os
import re
import subprocess
import sys
import tempfile
import time

src, relief = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
update = "--update" in sys.argv
build = os.path.dirname(relief)
failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL:", msg)


def pages():
    docs = os.path.join(src, "docs")
    names = sorted(f for f in os.listdir(docs) if f.endswith(".md"))
    return [os.path.join(src, "README.md")] + [os.path.join(docs, f) for f in names]


def slug(heading):
    """GitHub's anchor of a heading."""
    s = heading.strip().lower()
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def strip_code(text):
    return re.sub(r"```.*?```", "", text, flags=re.S)


def check_links(path, text):
    here = os.path.dirname(path)
    for target in re.findall(r"\]\(([^)\s]+)\)", strip_code(text)):
        if re.match(r"^[a-z]+:", target):
            continue
        file, _, anchor = target.partition("#")
        dest = os.path.normpath(os.path.join(here, file)) if file else path
        if not os.path.exists(dest):
            fail(f"{os.path.relpath(path, src)}: link {target}: no {os.path.relpath(dest, src)}")
            continue
        if anchor and dest.endswith(".md"):
            heads = re.findall(r"^#+ (.*)$", strip_code(open(dest).read()), flags=re.M)
            if anchor not in {slug(h) for h in heads}:
                fail(f"{os.path.relpath(path, src)}: link {target}: no such heading")


def commands():
    out = subprocess.run([relief, "--help"], capture_output=True, text=True).stdout
    block = out.split("commands:\n", 1)[1].split("\n\n", 1)[0]
    return re.findall(r"^  ([a-z][a-z-]*)", block, flags=re.M)


def generated(path, marker, make):
    """Each block of the page between <!-- MARKER[: ARG] --> and <!-- end
    MARKER --> must hold what make(ARG) returns, (text, what it is); None:
    nothing to compare. --update writes the text in."""
    text = open(path).read()
    pattern = re.compile(rf"(<!-- {marker}(?:: (\S+))? -->\n)(.*?)(<!-- end {marker} -->)", re.S)

    def block(m):
        made = make(m.group(2))
        if made is None:
            return m.group(0)
        want, what = made
        if m.group(3) != want and not update:
            fail(f"{os.path.relpath(path, src)}: {what} differs "
                 "(tests/docs/check_docs.py --update)")
        return m.group(1) + want + m.group(4)

    new = pattern.sub(block, text)
    if update and new != text:
        open(path, "w").write(new)
        print("updated", os.path.relpath(path, src))


def check_options(path, seen):
    """Each command's option table: what relief CMD --help-markdown prints."""
    def table(cmd):
        seen.add(cmd)
        out = subprocess.run([relief, cmd, "--help-markdown"], capture_output=True, text=True)
        return out.stdout, f"the option table of {cmd} against `relief {cmd} --help-markdown`"

    generated(path, "options", table)


def usages(_):
    """docs/usage.md's synopsis: every command's first --help line."""
    want = "```\n"
    for cmd in commands():
        out = subprocess.run([relief, cmd, "--help"], capture_output=True, text=True).stdout
        want += out.split("\n", 1)[0].replace("usage: ", "", 1) + "\n"
    return want + "```\n", "the usages against the commands' --help"


def api_index():
    """Every RELIEF_API function of include/relief/*.h, by header, with the
    first sentence of the comment above its declaration."""
    out = ""
    inc = os.path.join(src, "include", "relief")
    for name in sorted(os.listdir(inc)):
        if not name.endswith(".h"):
            continue
        text = open(os.path.join(inc, name)).read()
        rows = []
        for m in re.finditer(r"RELIEF_API\b[^;{]*?\b(relief_\w+)\s*\(", text):
            before = text[:m.start()].rstrip()
            doc = ""
            if before.endswith("*/"):
                start = before.rfind("/*")
                doc = re.sub(r"\s*\n\s*\*?\s*", " ", before[start + 2:-2]).strip(" *")
                doc = re.split(r"(?<=\.)\s", doc, 1)[0]
                doc = doc if len(doc) <= 240 else doc[:doc.rfind(" ", 0, 236)] + " ..."
            rows.append(f"| `{m.group(1)}` | {doc.replace('|', '/') or 'as the one above'} |")
        if rows:
            out += f"\n### `relief/{name}`\n\n| function | what it does |\n| --- | --- |\n"
            out += "\n".join(rows) + "\n"
    return out + "\n"


def examples(text):
    return re.findall(r"^```(sh|python) example\n(.*?)^```", text, flags=re.S | re.M)


def describe(v):
    if isinstance(v, dict):
        return ", ".join(f"`{k}`" for k in v) or "an empty object"
    if isinstance(v, list):
        inner = describe(v[0]) if v and isinstance(v[0], dict) else ""
        return "a list" + (f" of objects: {inner}" if inner else "")
    return {str: "a string", bool: "true or false", type(None): "null (not measured)",
            int: "a number", float: "a number"}[type(v)]


def report_table(file):
    """The members of a report an example wrote, one row each."""
    data = json.load(open(file))
    rows = [f"| `{k}` | {describe(v)} |" for k, v in data.items()]
    return "| member | holds |\n| --- | --- |\n" + "\n".join(rows) + "\n"


def check_reports(path, repo):
    """Each <!-- report: FILE --> table: the members of FILE, as the page's
    example wrote it."""
    def table(name):
        file = os.path.join(repo, name)
        if not os.path.exists(file):
            fail(f"{os.path.relpath(path, src)}: no example wrote {name}")
            return None
        return report_table(file), f"the report table of {name} against what the example wrote"

    generated(path, "report", table)


def run_examples(path, blocks, py):
    with tempfile.TemporaryDirectory() as tmp:
        repo = os.path.join(tmp, "repo")
        os.mkdir(repo)
        os.symlink(build, os.path.join(repo, "build"))
        os.symlink(os.path.join(src, "docs"), os.path.join(repo, "docs"))
        os.symlink(os.path.normpath(os.path.join(src, "..", "shared")),
                   os.path.join(tmp, "shared"))
        for n, (lang, code) in enumerate(blocks, 1):
            where = f"{os.path.relpath(path, src)} example {n}"
            if lang == "python":
                # No .venv (./setup.sh python not run): skipped, not a crash.
                if not os.path.exists(py) or subprocess.run(
                        [py, "-c", "import relief"], capture_output=True).returncode:
                    print(f"{where}: skipped ({py} cannot import relief)")
                    continue
                cmd = [py, "-c", code]
            else:
                cmd = ["bash", "-e", "-o", "pipefail", "-c", code]
            t = time.time()
            r = subprocess.run(cmd, cwd=repo, capture_output=True, text=True)
            if r.returncode:
                fail(f"{where} exited {r.returncode}:\n{code}{r.stderr[-2000:]}")
            else:
                print(f"{where}: ran in {time.time() - t:.1f} s")
        check_reports(path, repo)


def main():
    seen = set()
    py = os.path.join(src, ".venv", "bin", "python")
    run = os.environ.get("RELIEF_TEST_PASS") != "sanitize"
    total = 0
    for path in pages():
        text = open(path).read()
        check_links(path, text)
        check_options(path, seen)
        generated(path, "usages", usages)
        generated(path, "api", lambda _: (api_index(), "the function index against "
                                          "include/relief/*.h"))
        blocks = examples(open(path).read())
        total += len(blocks)
        if run and blocks:
            run_examples(path, blocks, py)
    for cmd in commands():
        if cmd not in seen:
            fail(f"relief {cmd}: no page in docs/ has its option table "
                 f"(<!-- options: {cmd} --> ... <!-- end options -->)")
    lines = sum(1 for _ in open(os.path.join(src, "README.md")))
    if lines >= 250:
        fail(f"README.md has {lines} lines: keep it under 250 (the rest belongs in docs/)")
    print(f"docs: {len(pages())} pages, {len(seen)} option tables, {total} examples"
          f"{'' if run else ' (not run in the sanitize pass)'}, README {lines} lines")
    sys.exit(1 if failures else 0)


main()
