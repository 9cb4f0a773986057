#!/usr/bin/python3
"""Checks the repository's documents: links that resolve, and no development bookkeeping.

    python3 tests/scripts/check_docs.py REPO_ROOT        one line per finding, exit 1; silent, exit 0 if none
    python3 tests/scripts/check_docs.py --self-test      checks this checker on a small temporary tree

(a) Every relative link of every tracked Markdown file (`git ls-files '*.md'`; without git, the tree less
    build*/ and .git) resolves: the file or folder exists, and a #anchor into a Markdown file (the same one
    or another) names a heading there by GitHub's rule (the heading's text lowercased, everything but
    letters, digits, spaces, '-' and '_' dropped, spaces turned into '-'; a repeated heading gets -1, -2,
    ...) or an explicit <a id=...> / <a name=...>. Inline links, image links, reference definitions and
    HTML href/src count; http(s), mailto and other schemes, and links inside fenced or indented code blocks
    and inline code, do not.
(b) No development bookkeeping in tracked .md, .cpp, .hpp, .py and .yaml files: numbered issues ("issue 30",
    "Issue #12"; an upstream one is written "yaml-cpp bug 1040" or "owner/repo#1040"), numbered stops,
    work periods, a "session" meaning a work period ("this session", "the sixth session"; comm::Session,
    an MPI or Gmsh session are code and pass), and machine nicknames ("the Intel kind", "this project's AMD
    machine"): a machine is named by its CPU model.

Python 3 standard library only.
"""
import os
import re
import subprocess
import sys
import tempfile
import urllib.parse

MD_SUFFIXES = (".md", ".markdown")
BOOKKEEPING_SUFFIXES = (".md", ".cpp", ".hpp", ".py", ".yaml")

# ----------------------------------------------------------------------------------------------------------
# Files

def tracked_files(root):
    """The repository's tracked files (paths relative to root, '/'-separated), or every file of the tree
    less build*/ and .git where git cannot say."""
    try:
        out = subprocess.run(["git", "-C", root, "ls-files", "-z"], stdout=subprocess.PIPE,
                             stderr=subprocess.DEVNULL, check=True).stdout
        files = [f for f in out.decode("utf-8", "replace").split("\0") if f]
        if files:
            return sorted(files)
    except (OSError, subprocess.CalledProcessError):
        pass
    files = []
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames[:] = sorted(d for d in dirnames if d != ".git" and not d.startswith("build"))
        for name in sorted(filenames):
            files.append(os.path.relpath(os.path.join(dirpath, name), root).replace(os.sep, "/"))
    return files


def read_lines(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        return f.read().splitlines()

# ----------------------------------------------------------------------------------------------------------
# Markdown structure: which lines are code, what the headings are

FENCE = re.compile(r"^ {0,3}(`{3,}|~{3,})")
LIST_ITEM = re.compile(r"^\s*(?:[-*+]|\d+[.)])\s")
ATX = re.compile(r"^ {0,3}(#{1,6})(?:[ \t]+(.*?))?(?:[ \t]+#+)?[ \t]*$")
SETEXT = re.compile(r"^ {0,3}(?:=+|-+)[ \t]*$")
HTML_ANCHOR = re.compile(r"""<a\s[^>]*?\b(?:id|name)\s*=\s*["']?([^"'\s>]+)""", re.IGNORECASE)
CODE_SPAN = re.compile(r"(`+)(.+?)\1")


def prose_lines(lines):
    """(line number, text) of each line outside fenced and indented code blocks."""
    out = []
    fence = None           # the opening fence's character and length while inside a fenced block
    prev_blank = True
    in_list = False
    in_indented_code = False
    for number, line in enumerate(lines, 1):
        if fence:
            m = FENCE.match(line)
            if m and m.group(1)[0] == fence[0] and len(m.group(1)) >= fence[1] and not line.strip(fence[0] + " \t"):
                fence = None
            prev_blank = False
            continue
        m = FENCE.match(line)
        if m and not in_indented_code:
            fence = (m.group(1)[0], len(m.group(1)))
            prev_blank = False
            continue
        blank = not line.strip()
        indented = line.startswith("    ") or line.startswith("\t")
        if in_indented_code and (indented or blank):
            prev_blank = blank
            continue
        in_indented_code = False
        if indented and prev_blank and not in_list and not blank:
            in_indented_code = True
            prev_blank = False
            continue
        if LIST_ITEM.match(line):
            in_list = True
        elif not blank and not indented and prev_blank:
            in_list = False
        out.append((number, line))
        prev_blank = blank
    return out


def strip_code_spans(text):
    return CODE_SPAN.sub(lambda m: " " * len(m.group(0)), text)


def heading_text(raw):
    """A heading's text as GitHub renders it (the part its anchor is made from)."""
    text = CODE_SPAN.sub(lambda m: m.group(2).strip(), raw)
    text = re.sub(r"!\[([^\]]*)\]\([^)]*\)", "", text)              # images: no text
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)             # links: their text
    text = re.sub(r"\[([^\]]*)\]\[[^\]]*\]", r"\1", text)            # reference links
    text = re.sub(r"<[^>]+>", "", text)                               # HTML tags
    text = re.sub(r"\\([!-/:-@\[-`{-~])", r"\1", text)               # backslash escapes
    text = text.replace("*", "")                                      # emphasis
    text = re.sub(r"(?<![\w])_+(?=\w)|(?<=\w)_+(?![\w])", "", text)  # _emphasis_, not d_c
    text = text.replace("&amp;", "&").replace("&lt;", "<").replace("&gt;", ">").replace("&quot;", '"')
    return text.strip()


def github_slug(text):
    text = text.lower()
    text = "".join(c for c in text if c.isalnum() or c in "-_ ")
    return text.replace(" ", "-")


def anchors_of(lines):
    """Every anchor a Markdown file offers: its headings' GitHub anchors and its explicit <a id/name>."""
    anchors = set()
    seen = {}
    prose = prose_lines(lines)

    def add_heading(raw):
        base = github_slug(heading_text(raw))
        slug = base
        if slug in seen:
            while True:
                seen[base] += 1
                slug = "%s-%d" % (base, seen[base])
                if slug not in seen:
                    break
        seen[slug] = 0
        anchors.add(slug)

    previous = None  # (number, text) of the previous prose line if it could be a setext heading's text
    for number, line in prose:
        for m in HTML_ANCHOR.finditer(strip_code_spans(line)):
            anchors.add(m.group(1).lower())
        m = ATX.match(line)
        if m:
            add_heading(m.group(2) or "")
            previous = None
        elif SETEXT.match(line) and previous and previous[0] == number - 1:
            add_heading(previous[1])
            previous = None
        elif line.strip() and not LIST_ITEM.match(line) and not line.lstrip().startswith(("|", ">")):
            previous = (number, line)
        else:
            previous = None
    return anchors

# ----------------------------------------------------------------------------------------------------------
# (a) links

LINK_START = re.compile(r"\]\(")
REFERENCE_DEFINITION = re.compile(r"^ {0,3}\[[^\]]+\]:\s*(\S+)")
HTML_LINK = re.compile(r"""<(?:a|img|source)\s[^>]*?\b(?:href|src)\s*=\s*["']([^"']+)["']""", re.IGNORECASE)
SCHEME = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:")


def link_destination(text, start):
    """The destination of an inline link whose '(' ends at start, or None."""
    i = start
    while i < len(text) and text[i] in " \t":
        i += 1
    if i < len(text) and text[i] == "<":
        end = text.find(">", i)
        return text[i + 1:end] if end > 0 else None
    depth = 0
    j = i
    while j < len(text):
        c = text[j]
        if c == "\\":
            j += 2
            continue
        if c in " \t":
            break
        if c == "(":
            depth += 1
        elif c == ")":
            if depth == 0:
                break
            depth -= 1
        j += 1
    return text[i:j] or None


def links_of(lines):
    """(line number, destination) of every link of a Markdown file outside code."""
    out = []
    for number, line in prose_lines(lines):
        text = strip_code_spans(line)
        m = REFERENCE_DEFINITION.match(text)
        if m:
            out.append((number, m.group(1).strip("<>")))
            continue
        for m in LINK_START.finditer(text):   # the link text may have begun on an earlier line
            dest = link_destination(text, m.end())
            if dest:
                out.append((number, dest))
        for m in HTML_LINK.finditer(text):
            out.append((number, m.group(1)))
    return out


def check_links(root, files):
    findings = []
    anchor_cache = {}

    def anchors(path):
        if path not in anchor_cache:
            anchor_cache[path] = anchors_of(read_lines(path))
        return anchor_cache[path]

    root_abs = os.path.abspath(root)
    for rel in files:
        if not rel.lower().endswith(MD_SUFFIXES):
            continue
        path = os.path.join(root_abs, rel)
        if not os.path.isfile(path):
            continue
        for number, dest in links_of(read_lines(path)):
            if SCHEME.match(dest) or dest.startswith("//"):
                continue
            target, _, anchor = dest.partition("#")
            target = urllib.parse.unquote(target.split("?", 1)[0])
            anchor = urllib.parse.unquote(anchor)
            if target:
                if target.startswith("/"):
                    target_path = os.path.normpath(os.path.join(root_abs, target.lstrip("/")))
                else:
                    target_path = os.path.normpath(os.path.join(os.path.dirname(path), target))
                if not os.path.exists(target_path):
                    findings.append("%s:%d: broken link '%s': no such file" % (rel, number, dest))
                    continue
            else:
                target_path = path
            if anchor and os.path.isfile(target_path) and target_path.lower().endswith(MD_SUFFIXES):
                if anchor.lower() not in anchors(target_path):
                    findings.append("%s:%d: broken anchor '%s': no such heading or <a id> in %s"
                                    % (rel, number, dest,
                                       os.path.relpath(target_path, root_abs).replace(os.sep, "/")))
    return findings

# ----------------------------------------------------------------------------------------------------------
# (b) development bookkeeping

_ORDINALS = (r"first|second|third|fourth|fifth|sixth|seventh|eighth|ninth|tenth|eleventh|twelfth|"
             r"\d+(?:st|nd|rd|th)")
# Words before "session" that make it code or a tool's session, not a work period.
_TOOL_SESSION = "".join(r"(?<!\b%s )" % w for w in (
    "MPI", "mpi", "Gmsh", "gmsh", "Python", "python", "ParaView", "interactive", "terminal", "shell", "ssh",
    "tmux", "login", "debugging", "debugger", "HTTP", "browser"))
_SESSION_WORD = _TOOL_SESSION + r"\bsessions?\b"  # lower case: Session is a class
_SESSION = _SESSION_WORD + r"(?!\s*[(;=&\[{])(?![._]\w)"  # not a variable
_MACHINE_WORDS = r"(?:intel|amd|arm|nvidia|epyc|xeon|gpu|h100|h200|a100|zen\s?\d?|sapphire rapids)"

# (pattern, a test of the line's text before the match that clears it)
BOOKKEEPING = [
    # "issue 30", "Issue #12", "issues 26 and 27"; "owner/repo issue 12" is an upstream reference
    (re.compile(r"(?<![\w/#.-])(?i:issues?)\s+#?\d+\b"), re.compile(r"[\w.-]+/[\w.-]+\s+$")),
    # numbered stops
    (re.compile(r"(?i:\bstops?)\s+#?\d+\b(?![.,]\d)(?!\s*(?i:ms|s|us|ns|mm|nm|m|%|steps?|times)\b)"), None),
    # work periods
    (re.compile(r"(?i:\bwork(?:ing)?[ -]periods?\b)"), None),
    (re.compile(r"(?i:\bperiod)\s+#?\d+\b(?![.,]\d)(?!\s*(?i:ms|s|us|ns|steps?|hz)\b)"), None),
    # a session meaning a work period: "this session", "the sixth session", "a session starts", "session 4",
    # "the session of 2026-12-01"
    (re.compile(r"(?i:\b(?:a|an|this|that|these|those|each|every|one|two|three|several|earlier|later|previous|"
                r"next|last|same|new|own|" + _ORDINALS + r"))\s+(?:[\w-]+\s+)?" + _SESSION), None),
    (re.compile(_SESSION_WORD + r"\s+(?:#?\d+\b|(?:of|on)\s+\d{4}-\d\d-\d\d)"), None),
    # machine nicknames: "the Intel kind", "this project's AMD machine"
    (re.compile(r"(?i:\b(?:the|this|that|an?|its)\s+(?:" + _MACHINE_WORDS + r"\s+){1,3}(?:machine\s+)?kinds?\b)"),
     None),
    (re.compile(r"(?i:\bthis\s+project(?:'|\u2019)s\s+(?:[\w-]+\s+){0,3}?"
                r"(?:machines?|kinds?|vms?|boxe?s?|computers?)\b)"), None),
]


def check_bookkeeping(root, files, skip=()):
    findings = []
    for rel in files:
        if not rel.lower().endswith(BOOKKEEPING_SUFFIXES) or rel in skip:
            continue
        path = os.path.join(root, rel)
        if not os.path.isfile(path):
            continue
        for number, line in enumerate(read_lines(path), 1):
            spans = []
            for pattern, cleared_by in BOOKKEEPING:
                for m in pattern.finditer(line):
                    if cleared_by and cleared_by.search(line[:m.start()]):
                        continue
                    if not any(a <= m.start() < b for a, b in spans):
                        spans.append((m.start(), m.end()))
            for a, b in sorted(spans):
                findings.append("%s:%d: development bookkeeping: '%s'" % (rel, number, line[a:b]))
    return findings

# ----------------------------------------------------------------------------------------------------------

def check(root):
    files = tracked_files(root)
    # This file names the phrases it looks for, so it is the one file they may stand in.
    this_file = os.path.relpath(os.path.realpath(__file__), os.path.realpath(root)).replace(os.sep, "/")
    return check_links(root, files) + check_bookkeeping(root, files, skip=(this_file,))


def self_test():
    """A small tree with a broken link, a broken anchor, a good anchor and one bookkeeping phrase, among
    text that must pass; exactly those three findings must come out."""
    # Phrases are assembled so that this file itself holds none of them.
    work = "ses" + "sion"
    files = {
        "README.md": "\n".join([
            "# The project",
            "",
            "## Results: d_c and `code` (at 2.5 nm)",
            "",
            "## Results: d_c and `code` (at 2.5 nm)",
            "",
            "<a id=\"explicit-place\"></a>",
            "See [the guide](docs/guide.md#getting-started), [again](docs/guide.md#getting-started-1),",
            "[a result](#results-d_c-and-code-at-25-nm), [its twin](#results-d_c-and-code-at-25-nm-1),",
            "[the place](#explicit-place), ![a picture](docs/pic.png), [a folder](docs/),",
            "[the web](https://example.org/x#y \"a title\"), [mail](mailto:a@b.c), <https://example.org>.",
            "[missing](docs/missing.md) is broken.",
            "[bad anchor](docs/guide.md#no-such-heading) is broken.",
            "`[in code](nowhere.md)` is not a link.",
            "",
            "```",
            "[in a fence](nowhere_either.md)",
            "```",
            "",
            "    [indented code](nowhere_at_all.md)",
            "",
            "The MPI " + work + " starts first; comm::Session holds it; yaml-cpp bug 1040; lammps/lammps#4666.",
            "",
        ]) + "\n",
        "docs/guide.md": "# Guide\n\n## Getting started\n\ntext\n\n## Getting started\n\nmore\n",
        "docs/pic.png": "not really a picture\n",
        "src/a.cpp": "// The thermo every N steps.\n"
                     "int main(int argc, char** argv) { comm::Session " + work + "(&argc, &argv); }\n"
                     "// measured in the sixth " + work + " on a busy machine\n",
    }
    expected = [
        "README.md:12: broken link 'docs/missing.md': no such file",
        "README.md:13: broken anchor 'docs/guide.md#no-such-heading': no such heading or <a id> in docs/guide.md",
        "src/a.cpp:3: development bookkeeping: 'sixth " + work + "'",
    ]
    with tempfile.TemporaryDirectory(prefix="check_docs_") as root:
        for rel, text in files.items():
            path = os.path.join(root, rel)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "w", encoding="utf-8") as f:
                f.write(text)
        found = check(root)
    if found != expected:
        sys.stderr.write("check_docs.py --self-test: expected\n  %s\nfound\n  %s\n"
                         % ("\n  ".join(expected), "\n  ".join(found) or "(nothing)"))
        return 1
    return 0


def main(argv):
    if argv[1:] == ["--self-test"]:
        return self_test()
    if len(argv) != 2 or argv[1].startswith("-"):
        sys.stderr.write("usage: check_docs.py REPO_ROOT | --self-test\n")
        return 2
    if not os.path.isdir(argv[1]):
        sys.stderr.write("check_docs.py: no folder %s\n" % argv[1])
        return 2
    findings = check(argv[1])
    for line in findings:
        print(line)
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
