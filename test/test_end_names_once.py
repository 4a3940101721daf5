"""The two end names are defined once (physics/boundary.py END_NAMES): no other product module spells
them out as a pair or keeps its own alias of them, so a reader finds one list and a change of the
ends cannot leave a copy behind. Plain text scan of tether_sim/, well under a second."""

import pathlib
import re

ROOT = pathlib.Path(__file__).resolve().parents[1] / "tether_sim"
HOME = ROOT / "physics" / "boundary.py"
PAIR = re.compile(r"""[(\[]\s*(["'])ship\1\s*,\s*(["'])vehicle\2""")
ALIAS = re.compile(r"^\w+\s*=\s*END_NAMES\s*$|^ENDS\s*=", re.M)  # a module-level alias


def test_the_patterns_catch_their_examples():
    assert PAIR.search('for end in ("ship", "vehicle"):') and PAIR.search("['ship', 'vehicle']")
    assert PAIR.search('("ship", "vehicle", "span")') and not PAIR.search('("ship", "span")')
    assert ALIAS.search("ENDS = END_NAMES\n") and ALIAS.search('ENDS = ("ship", "vehicle")\n')
    assert not ALIAS.search("    ends = END_NAMES\n")  # a local name in a function is not a second list


def test_the_end_names_are_written_once():
    found = []
    for f in sorted(ROOT.rglob("*.py")):
        text = f.read_text()
        for rx in (PAIR, ALIAS):
            for m in rx.finditer(text):
                if f == HOME and m.group(0).strip().startswith(("END_NAMES", "(")):
                    continue
                found.append(f"{f.relative_to(ROOT.parent)}:{text.count(chr(10), 0, m.start()) + 1}: {m.group(0).strip()}")
    assert found == [], "\n".join(found)
