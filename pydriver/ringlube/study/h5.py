"""HDF5 pieces of a study file shared by its records: labelled matrices and UTF-8 strings.

Every record of :mod:`ringlube.study.state` and :mod:`ringlube.study.state_checks`, and
:class:`~ringlube.study.surrogate.QuadraticSurface`, writes itself with these in ``to_h5`` and reads
itself back in ``from_h5``; :mod:`ringlube.study.layout` composes them into a case and
:class:`~ringlube.study.store.Study` writes the file's attributes and samples with them.
"""

from __future__ import annotations

from typing import Any

import h5py
import numpy as np

__all__ = ["STR", "text", "put", "put_strings", "strings"]

#: HDF5 type of every string dataset and string-list attribute (variable-length UTF-8).
STR = h5py.string_dtype("utf-8")


def text(value: Any) -> str:
    """A string attribute or dataset element as ``str`` (bytes decoded as UTF-8).

    Parameters
    ----------
    value : str, bytes or numpy.bytes_

    Returns
    -------
    str

    Example
    -------
    >>> text(b"cold"), text("hot")
    ('cold', 'hot')
    """
    if isinstance(value, (bytes, np.bytes_)):
        return bytes(value).decode(errors="replace")
    return str(value)


def put(
    parent: h5py.Group, name: str, data: Any, columns: list[str] | None = None, units: list[str] | None = None
) -> h5py.Dataset:
    """Write ``data`` as dataset ``name`` with optional ``columns`` and ``units`` attributes.

    Parameters
    ----------
    parent : h5py.Group
    name : str
        Dataset path below ``parent`` (intermediate groups are created).
    data : array_like
    columns, units : list of str, optional
        Labels of the last axis, stored as UTF-8 string attributes.

    Returns
    -------
    h5py.Dataset

    Example
    -------
    >>> with h5py.File("x.h5", "w", driver="core", backing_store=False) as f:
    ...     d = put(f, "front/x", np.zeros((2, 1)), ["width"], ["m"])
    ...     [text(u) for u in d.attrs["units"]]
    ['m']
    """
    d = parent.create_dataset(name, data=np.asarray(data))
    if columns is not None:
        d.attrs.create("columns", np.array(columns, dtype=object), dtype=STR)
    if units is not None:
        d.attrs.create("units", np.array(units, dtype=object), dtype=STR)
    return d


def put_strings(parent: h5py.Group, name: str, values: list[str]) -> None:
    """Write a list of strings as a UTF-8 string dataset.

    Parameters
    ----------
    parent : h5py.Group
    name : str
    values : list of str

    Example
    -------
    >>> with h5py.File("x.h5", "w", driver="core", backing_store=False) as f:
    ...     put_strings(f, "names", ["knee", "reference"])
    ...     strings(f["names"])
    ['knee', 'reference']
    """
    parent.create_dataset(name, data=np.array(values, dtype=object), dtype=STR)


def strings(d: h5py.Dataset) -> list[str]:
    """A string dataset as a list of ``str``.

    Parameters
    ----------
    d : h5py.Dataset

    Returns
    -------
    list of str

    Example
    -------
    >>> with h5py.File("x.h5", "w", driver="core", backing_store=False) as f:
    ...     put_strings(f, "errors", ["", "no film"])
    ...     strings(f["errors"])
    ['', 'no film']
    """
    return [text(v) for v in d[()]]
