"""The studies' per-run records: frozen dataclasses, written as JSON objects and read back.

A study's task returns one record per run (a frozen dataclass built by keyword, its fields
documented in its numpydoc ``Attributes``); the summariser reads its attributes, the runner
writes it to ``<study>_runs.json`` through :func:`~rankedassign.experiments.report.write_json`
(:func:`dataclasses.asdict`, field by field in the class's order), and
:meth:`RunRecord.from_dict` builds it again from that JSON object. The classes live at module
level, so that the records pickle to and from worker processes (Dask included).
"""

from __future__ import annotations

import dataclasses
import warnings

__all__ = ["RunRecord"]


class RunRecord:
    """Base of a study's per-run record (a frozen dataclass): its plain-data form and back.

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> @dataclass(frozen=True)
    ... class Run(RunRecord):
    ...     run: int
    ...     error: float
    >>> Run.from_dict(Run(run=0, error=0.5).to_dict())
    Run(run=0, error=0.5)
    """

    def __getitem__(self, key: str):
        """A field by name, as the dicts the tasks returned before the records (deprecated).

        Parameters
        ----------
        key : str
            A field's name.

        Returns
        -------
        object
            The field's value (``record[key]`` is ``record.key``).

        Raises
        ------
        KeyError
            If the record has no field ``key``.

        Examples
        --------
        >>> import warnings
        >>> from dataclasses import dataclass
        >>> @dataclass(frozen=True)
        ... class Run(RunRecord):
        ...     error: float
        >>> with warnings.catch_warnings():
        ...     warnings.simplefilter("ignore", DeprecationWarning)
        ...     Run(error=0.5)["error"]
        0.5
        """
        if not isinstance(key, str) or key not in {f.name for f in dataclasses.fields(self)}:
            raise KeyError(key)
        warnings.warn(f"{type(self).__name__}[{key!r}]: a study task returns a record now; "
                      f"read its attribute ({type(self).__name__}.{key}) instead; the dict "
                      "access goes in the next release", DeprecationWarning, stacklevel=2)
        return getattr(self, key)

    def to_dict(self) -> dict:
        """The record as a dict of its fields, in the class's order.

        Returns
        -------
        dict
            :func:`dataclasses.asdict` of the record (nested records as dicts too): the object
            ``<study>_runs.json`` holds, before NaN becomes ``null``.
        """
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, data: dict):
        """The record whose plain-data form is ``data`` (a JSON object read back).

        Parameters
        ----------
        data : dict
            The record's fields by name (a field with a default may be missing). A subclass
            whose fields hold records of their own converts them (it overrides this method).

        Returns
        -------
        RunRecord
            A record of this class.

        Raises
        ------
        ValueError
            If ``data`` is not a mapping, or names a field the class does not have.
        """
        if not isinstance(data, dict):
            raise ValueError(f"{cls.__name__}.from_dict needs a mapping of its fields, got "
                             f"{type(data).__name__}")
        unknown = sorted(set(data) - {f.name for f in dataclasses.fields(cls)})
        if unknown:
            raise ValueError(f"{cls.__name__}.from_dict: unknown field(s) {unknown}")
        return cls(**data)
