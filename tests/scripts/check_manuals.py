#!/usr/bin/env python3
"""Each executable's manual holds its key and column tables exactly as the executable prints them.

    python3 tests/scripts/check_manuals.py --bin build/bin [--root .] [--update]

For every executable, the text between `<!-- keys: begin -->` and `<!-- keys: end -->` in its manual must
equal `<exe> --keys`, and the text between `<!-- columns: begin -->` and `<!-- columns: end -->` must equal
`<exe> --columns`: a key added to a reader's reference and not to the manual, or a manual row the reference
no longer has, fails. Every described key must also be named (as "key") somewhere in the readers' sources,
so a description left behind by a removed key fails too. `--update` rewrites the blocks from the executables
(then review the diff). Exit 1 with one line per finding.
"""
import argparse
import pathlib
import re
import subprocess
import sys

MANUALS = {
    "debris_dem": "scenarios/dem/README.md",
    "debris_peridem": "scenarios/peridem/README.md",
    "debris_patch": "scenarios/patch/README.md",
    "debris_amorphous": "scenarios/amorphous/README.md",
    "debris_calibrate": "scenarios/calibrate/README.md",
    "debris_restitution": "scenarios/restitution/README.md",
}
BLOCKS = {"keys": "--keys", "columns": "--columns"}


def block_pattern(name):
    return re.compile(r"(<!-- %s: begin -->\n)(.*?)(<!-- %s: end -->)" % (name, name), re.S)


def printed(exe, flag):
    out = subprocess.run([str(exe), flag], capture_output=True, text=True, timeout=60)
    if out.returncode != 0:
        raise RuntimeError("%s %s: exit %d: %s" % (exe.name, flag, out.returncode, out.stderr.strip()))
    return out.stdout


def source_text(root):
    parts = []
    for folder in ("core", "scenarios"):
        for p in sorted((root / folder).rglob("*.cpp")):
            parts.append(p.read_text(errors="replace"))
    return "\n".join(parts)


def described_keys(markdown):
    """Key paths of the generated tables: the first cell of each row."""
    return re.findall(r"^\| `([^`]+)` \|", markdown, re.M)


def check(root, bin_dir, update):
    findings = []
    sources = source_text(root)
    for exe_name, manual in MANUALS.items():
        exe = bin_dir / exe_name
        path = root / manual
        if not exe.exists():
            findings.append("%s: not built (%s)" % (exe_name, exe))
            continue
        if not path.exists():
            findings.append("%s: the manual of %s is missing" % (manual, exe_name))
            continue
        text = path.read_text()
        for name, flag in BLOCKS.items():
            want = printed(exe, flag)
            pattern = block_pattern(name)
            match = pattern.search(text)
            if not match:
                findings.append("%s: no '<!-- %s: begin -->' ... '<!-- %s: end -->' block for `%s %s`"
                                % (manual, name, name, exe_name, flag))
                continue
            if match.group(2) != want:
                if update:
                    text = text[:match.start(2)] + want + text[match.end(2):]
                    continue
                have_rows = set(match.group(2).splitlines())
                want_rows = set(want.splitlines())
                for row in sorted(want_rows - have_rows):
                    findings.append("%s: `%s %s` prints a line the manual lacks: %s" % (manual, exe_name, flag, row))
                for row in sorted(have_rows - want_rows):
                    findings.append("%s: a line `%s %s` no longer prints: %s" % (manual, exe_name, flag, row))
                if want_rows == have_rows:
                    findings.append("%s: the %s block holds `%s %s`'s lines in another order" % (manual, name, exe_name, flag))
            if name == "keys":
                for key in described_keys(want):
                    last = key.split(".")[-1]
                    if last.startswith("<"):
                        continue
                    if '"%s"' % last not in sources:
                        findings.append("%s: the key '%s' is described but no reader in core/ or scenarios/ names \"%s\""
                                        % (exe_name, key, last))
        if update:
            path.write_text(text)
    return findings


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", required=True, help="directory of the built executables")
    ap.add_argument("--root", default=str(pathlib.Path(__file__).resolve().parents[2]), help="repository root")
    ap.add_argument("--update", action="store_true", help="rewrite the generated blocks of the manuals")
    args = ap.parse_args()
    findings = check(pathlib.Path(args.root), pathlib.Path(args.bin), args.update)
    for f in findings:
        print(f)
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
