"""The generated sections of docs/performance.md: ``<!-- begin:NAME -->`` ... ``<!-- end:NAME -->``.

Every benchmark that writes its results into the docs puts its section there with
:func:`write_section` (``from doc_sections import write_section``: the scripts run from
this folder).
"""

from __future__ import annotations

import re
from pathlib import Path


def write_section(text: str, path: Path) -> None:
    """Put the ``<!-- begin:NAME -->`` ... ``<!-- end:NAME -->`` section ``text`` into
    ``path``, replacing the section of the same name or appending it."""
    name = re.search(r"<!-- begin:(\w+) -->", text).group(1)
    old = path.read_text() if path.exists() else ""
    pat = re.compile(rf"<!-- begin:{name} -->.*?<!-- end:{name} -->\n?", re.S)
    new = pat.sub(lambda _: text, old) if pat.search(old) else old.rstrip("\n") + "\n\n" + text
    path.write_text(new)
