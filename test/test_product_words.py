"""The product speaks of the product: no work-log words in code, configuration, docs or tests.

A figure or a decision is dated (2026-11-26) and names the command that produced it; "session 2",
"issue 15 item 4" or a branch name such as "s4-surface" mean nothing to a reader of the repository.
Nor does a path outside the repository (a reader does not have it). Plain text scan, well under a
second.
"""

import pathlib
import re

ROOT = pathlib.Path(__file__).resolve().parents[1]
SCANNED = ["tether_sim", "config", "docs", "test", "benchmarks", "tools", "launch", "msg_defs", "README.md",
           "BENCHMARKS.md", "Makefile", "setup.py", "setup.cfg", "package.xml"]
SUFFIXES = {".py", ".md", ".yaml", ".yml", ".cfg", ".toml", ".txt", ".msg", ".sh", ".xml", ".csv", ""}

# each pattern with an example it must catch (checked below, so a broken pattern cannot pass silently)
PATTERNS = {
    "work-log session": (re.compile(r"\bsessions? ?-?\d|\bsession-\d", re.I), "as measured in Session 3"),
    "issue number": (re.compile(r"\bissues? ?#?\d", re.I), "the acceptance of issue 15 item 4"),
    "branch name": (re.compile(r"\bs\d+-[a-z]{3,}\b"), "(branch s4-surface)"),
    "path outside the repository": (re.compile(r"(?<![\w.])/(?:work|home|root)/\w"), "see /work/shared/notes/x.md"),
}


def _files():
    for entry in SCANNED:
        p = ROOT / entry
        paths = [p] if p.is_file() else sorted(p.rglob("*")) if p.is_dir() else []
        for f in paths:
            if (f.is_file() and f.suffix in SUFFIXES and "__pycache__" not in f.parts
                    and f != pathlib.Path(__file__).resolve()):
                yield f


def test_patterns_catch_their_examples():
    for name, (rx, example) in PATTERNS.items():
        assert rx.search(example), name
    # and leave the library words alone
    for legit in ("start_new_session=True", '@pytest.fixture(scope="session")', "Test-session set-up",
                  "issues of the solver", "s = 0 at the ship end"):
        assert not any(rx.search(legit) for rx, _ in PATTERNS.values()), legit


def test_no_work_log_words_in_the_product():
    hits = []
    n_files = 0
    for f in _files():
        n_files += 1
        try:
            text = f.read_text(encoding="utf-8")
        except UnicodeDecodeError:
            continue
        for lineno, line in enumerate(text.splitlines(), 1):
            for name, (rx, _) in PATTERNS.items():
                m = rx.search(line)
                if m:
                    hits.append(f"{f.relative_to(ROOT)}:{lineno}: {name}: {m.group(0)!r}")
    assert n_files > 100  # the scan saw the repository
    assert not hits, "replace with a date, a command or a reason:\n" + "\n".join(hits)
