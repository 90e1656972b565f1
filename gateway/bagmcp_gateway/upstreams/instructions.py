"""The gateway's one instructions text, made from what its upstreams' instructions say.

Each sentence appears once: first those several upstreams share (the conventions every service repeats:
bags, times, message paths), then the sentences only one upstream states (what each is for), in
configuration order. Conventions go first because clients cut instructions: Claude Code keeps the first
2,048 characters without telling the server (tests/unit/gateway/test_tool_surface.py keeps the whole text
under that).
"""

from __future__ import annotations

import re
from collections import Counter
from collections.abc import Sequence

# A sentence ends at . ! or ? followed by a space and a capital or a backquote ("e.g. pose" does not end one).
_SENTENCE_END = re.compile(r"(?<=[.!?])\s+(?=[A-Z`])")


def sentences(text: str) -> list[str]:
    return [s.strip() for s in _SENTENCE_END.split(text) if s.strip()]


def merged_instructions(texts: Sequence[str | None]) -> str | None:
    """One text from several servers' instructions (None when none has any)."""
    per_text = [list(dict.fromkeys(sentences(t))) for t in texts if t]
    counts = Counter(s for found in per_text for s in found)
    ordered = list(dict.fromkeys(s for found in per_text for s in found))
    own = [s for s in ordered if counts[s] == 1]
    shared = [s for s in ordered if counts[s] > 1]
    return " ".join(shared + own) or None
