"""Errors the Python half raises, of the same shape as the native ones (kind, path, param, message, errors)."""

from __future__ import annotations

from typing import Optional

from ._geode import GeodeError


class NotFoundError(GeodeError, KeyError):
    """A node, parameter or attribute that is not there. A ``KeyError`` too,
    so mappings and ``except KeyError`` work as with any Python lookup."""

    def __init__(self, kind: str, path: Optional[str], param: Optional[str], message: str):
        where = f"{path} (parameter `{param}`)" if path and param else (path or "")
        super().__init__(f"{where}: {message}" if where else message)
        self.kind = kind
        self.path = path
        self.param = param
        self.message = message
        self.errors = [{"kind": kind, "path": path, "param": param, "message": message}]

    def __str__(self) -> str:
        # KeyError's own __str__ would quote the message as a key.
        return str(self.args[0])
