#!/usr/bin/env bash
# Checks the documentation's references (run by tests/docs/docs_links_test.cpp, i.e. by
# `./scripts/dev.sh test` and CI):
#   - every relative Markdown link or image, [text](path#anchor), names a file or folder of the
#     repository, and its #anchor (if any) a heading of that file (GitHub's heading ids);
#   - every repository path cited in the text (runtime/..., kernels/..., host/..., drivers/...,
#     tests/..., bench/..., presets/..., scripts/..., docs/..., cmake/..., .ci/...) exists;
#     globs (*, **) must match something, {a,b} is expanded, <placeholders> are skipped, and
#     ../shared/... is checked where that folder exists;
#   - every top-level file cited in backticks (`CMakeLists.txt`, `README.md`: a name with no
#     folder, a capital first letter and a .md, .txt, .json, .yml or .yaml ending) exists at the
#     repository's root or beside the citing file (placeholders such as `NAME.md` are skipped).
# Files checked: README.md, docs/*.md, bench/*.md (or the files given as arguments).
# scripts/check_links.allow lists broken references that are reported as warnings (with why);
# an entry that matches nothing broken any more is an error, so fixed entries are removed.
# Prints one line per broken reference (file:line: what) and exits 1 when there is any.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -eq 0 ]; then
  set -- README.md docs/*.md bench/*.md
fi
exec python3 - "$@" <<'PY'
import glob, os, re, sys

ROOTS = r"(?:runtime|kernels|host|drivers|tests|bench|presets|scripts|docs|cmake|\.ci|\.\./shared)"
PATH_RE = re.compile(r"(?<![\w./\-])(" + ROOTS + r"/[\w./*{},\-<>]*)")
LINK_RE = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
TOP_RE = re.compile(r"`([A-Z][\w\-]*\.(?:md|txt|json|ya?ml))`")
PLACEHOLDERS = {"NAME", "FILE", "PATH", "DIR", "PREFIX", "OUT"}
shared_exists = os.path.isdir("../shared")


def slug(heading, seen):
    s = heading.strip().lower()
    s = re.sub(r"[`*_]", lambda m: "_" if m.group(0) == "_" else "", s)
    s = re.sub(r"[^\w\- ]", "", s)
    s = s.replace(" ", "-")
    n = seen.get(s, 0)
    seen[s] = n + 1
    return s if n == 0 else f"{s}-{n}"


anchor_cache = {}


def anchors(path):
    if path not in anchor_cache:
        seen, out, fence = {}, set(), False
        with open(path, encoding="utf-8") as f:
            for line in f:
                if line.startswith("```"):
                    fence = not fence
                m = None if fence else re.match(r"#{1,6}\s+(.*?)\s*#*\s*$", line)
                if m:
                    out.add(slug(m.group(1), seen))
        anchor_cache[path] = out
    return anchor_cache[path]


def expand_braces(p):
    m = re.search(r"\{([^{}]*)\}", p)
    if not m:
        return [p]
    out = []
    for alt in m.group(1).split(","):
        out += expand_braces(p[: m.start()] + alt + p[m.end():])
    return out


def path_exists(p):
    if any(c in p for c in "*?["):
        return bool(glob.glob(p, recursive=True))
    return os.path.exists(p)


allowed = {}
with open("scripts/check_links.allow", encoding="utf-8") as f:
    for line in f:
        line = line.split("    (")[0].strip()
        if line and not line.startswith("#"):
            doc, _, cited = line.partition(": ")
            allowed[(doc, cited.strip())] = False

errors = []


def broken(doc, where, cited, message):
    if (doc, cited) in allowed:
        allowed[(doc, cited)] = True
        print(f"{where}: {message} (known: scripts/check_links.allow)")
    else:
        errors.append(f"{where}: {message}")


for doc in sys.argv[1:]:
    base = os.path.dirname(doc)
    with open(doc, encoding="utf-8") as f:
        lines = f.read().split("\n")
    for no, line in enumerate(lines, 1):
        where = f"{doc}:{no}"
        # Markdown links and images.
        for m in LINK_RE.finditer(line):
            target = m.group(1)
            if re.match(r"[a-z][a-z0-9+.-]*:", target):  # http:, https:, mailto:
                continue
            path, _, anchor = target.partition("#")
            file = os.path.normpath(os.path.join(base, path)) if path else doc
            if not os.path.exists(file):
                broken(doc, where, target, f"link to {target}: {file} does not exist")
            elif anchor and file.endswith(".md") and anchor not in anchors(file):
                broken(doc, where, target, f"link to {target}: no heading #{anchor} in {file}")
        # Paths cited in the text (outside link targets, which are checked above).
        text = LINK_RE.sub(lambda m: m.group(0).split("](")[0], line)
        for m in PATH_RE.finditer(text):
            p = m.group(1).rstrip(".,;:")
            if "<" in p or ">" in p:
                continue
            p = re.sub(r":\d+$", "", p)
            if p.startswith("../shared/") and not shared_exists:
                continue
            for q in expand_braces(p):
                if not path_exists(q):
                    broken(doc, where, q, f"cites {q}, which does not exist")
        # Top-level files cited in backticks.
        for m in TOP_RE.finditer(line):
            name = m.group(1)
            if name.split(".")[0] in PLACEHOLDERS:
                continue
            if not (os.path.exists(name) or os.path.exists(os.path.join(base, name))):
                broken(doc, where, name, f"cites {name}, which does not exist")

for (doc, cited), used in allowed.items():
    if not used and doc in sys.argv[1:]:
        errors.append(f"scripts/check_links.allow: {doc}: {cited} is no longer broken; remove it")
for e in errors:
    print(e)
if errors:
    print(f"check_links.sh: {len(errors)} broken reference(s)", file=sys.stderr)
    sys.exit(1)
print(f"check_links.sh: {len(sys.argv) - 1} files, every link and cited path exists")
PY
