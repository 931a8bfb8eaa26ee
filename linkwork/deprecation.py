"""Deprecated names kept working: renamed keywords, functions and attributes.

linkwork keeps every public name that an earlier version documented. When a name changes (to
give one concept one name across the package, see ``docs/nomenclature.md``), the old name keeps
working and emits a :class:`DeprecationWarning` that names its replacement:

* :func:`renamed_keywords` -- a keyword argument renamed (``on_fail=`` -> ``on_failure=``);
* :func:`renamed_function` -- a function renamed (the old name calls the new one);
* :func:`renamed_attribute` -- a result field renamed (a read-only property under the old name).
"""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable
from typing import Any, TypeVar

__all__ = ["renamed_attribute", "renamed_function", "renamed_keywords", "warn_renamed"]

F = TypeVar("F", bound=Callable[..., Any])


def warn_renamed(old: str, new: str, *, stacklevel: int = 3) -> None:
    """Emit the one deprecation message of linkwork: ``old`` is now called ``new``."""
    warnings.warn(f"{old} is deprecated: use {new} (same meaning, same values)",
                  DeprecationWarning, stacklevel=stacklevel)


def renamed_keywords(**old_to_new: str) -> Callable[[F], F]:
    """Accept the old names of renamed keyword arguments, with a warning.

    ``@renamed_keywords(on_fail="on_failure")`` lets ``f(..., on_fail="nan")`` call
    ``f(..., on_failure="nan")``; giving both names is a TypeError.
    """

    def wrap(func: F) -> F:
        @functools.wraps(func)
        def inner(*args: Any, **kwargs: Any) -> Any:
            for old, new in old_to_new.items():
                if old in kwargs:
                    if new in kwargs:
                        raise TypeError(f"{func.__name__}() got both {old}= (deprecated) and "
                                        f"{new}=; give only {new}=")
                    warn_renamed(f"{func.__name__}({old}=...)", f"{new}=")
                    kwargs[new] = kwargs.pop(old)
            return func(*args, **kwargs)

        return inner  # type: ignore[return-value]

    return wrap


def renamed_function(func: F, old: str) -> F:
    """The function ``func`` under its former name ``old``, warning at each call."""

    @functools.wraps(func)
    def inner(*args: Any, **kwargs: Any) -> Any:
        warn_renamed(f"{old}()", f"{func.__module__}.{func.__name__}()")
        return func(*args, **kwargs)

    inner.__name__ = inner.__qualname__ = old
    inner.__doc__ = f"Deprecated name of :func:`{func.__module__}.{func.__name__}`."
    return inner  # type: ignore[return-value]


def renamed_attribute(new: str, old: str) -> property:
    """A read-only property ``old`` that returns the attribute ``new``, with a warning."""

    def get(self: Any) -> Any:
        warn_renamed(f"{type(self).__name__}.{old}", f".{new}")
        return getattr(self, new)

    return property(get, doc=f"Deprecated name of ``{new}``.")
