"""A griffe extension for the API reference: crd's docstrings use reStructuredText roles
(``:mod:`cosim.loop```, ``:func:`x```), which Markdown would show as written; they become code spans.

Registered in ``mkdocs.yml`` (mkdocstrings' python handler, ``extensions``).
"""

from __future__ import annotations

import re
from typing import Any

from griffe import Extension, Object

_ROLE = re.compile(r":(?:py:)?(?:mod|func|class|meth|attr|data|obj|exc|const|ref):`~?([^`]+)`")


class SphinxRoles(Extension):
    """``:role:`target``` -> ```target``` in every docstring, when griffe loads an object."""

    def on_object(self, *, obj: Object, **kwargs: Any) -> None:
        if obj.docstring is not None:
            obj.docstring.value = _ROLE.sub(r"`\1`", obj.docstring.value)
