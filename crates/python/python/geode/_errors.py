"""Errors the Python half raises, with the fields every geode error carries (kind, path, param, message, errors)."""

from __future__ import annotations

from typing import Optional, TypeVar

from ._geode import GeodeError, InvalidValueError, NotFoundError

E = TypeVar("E", bound=GeodeError)


def error(cls: type[E], kind: str, path: Optional[str], param: Optional[str], message: str) -> E:
    """An exception of ``cls`` with its fields set, worded as the native ones are."""
    where = f"{path} (parameter `{param}`)" if path and param else (path or "")
    e = cls(f"{where}: {message}" if where else message)
    e.kind, e.path, e.param, e.message = kind, path, param, message
    e.errors = [{"kind": kind, "path": path, "param": param, "message": message}]
    return e


def not_found(kind: str, path: Optional[str], param: Optional[str], message: str) -> NotFoundError:
    """A node, parameter or attribute that is not there."""
    return error(NotFoundError, kind, path, param, message)


def invalid(message: str, path: Optional[str] = None, param: Optional[str] = None) -> InvalidValueError:
    """A value geode cannot use."""
    return error(InvalidValueError, "value", path, param, message)
