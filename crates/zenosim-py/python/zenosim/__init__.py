"""zenosim: hybrid Lagrangian systems with impacts, carried through and past their Zeno points.

A model is a hybrid Lagrangian in a TOML model file (see the project's README)::

    import zenosim

    model = zenosim.Model.from_file("models/ball-on-sine.toml")
    run = zenosim.run(model, t_end=6.0)
    run.status, run.zeno[0]["t_zeno"]      # ('finished', 2.0456...)
    run.t, run.q, run.q_dot                # numpy arrays, one row per step and around each event

    table = zenosim.sweep(model, {"e": [0.5, 0.6, 0.7]})
    table["t_zeno"]                        # one run per value, in parallel
    table.to_pandas()                      # a pandas DataFrame, where pandas is installed

The GIL is released while simulating; Ctrl-C raises ``KeyboardInterrupt`` within about 50 ms.
A run that fails is no exception: its ``status`` says so, with what was computed. A model that
zenosim refuses raises :class:`ModelError`.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Literal, Mapping, Sequence, Union

from ._zenosim import Model, ModelError, Run, __version__, run
from . import _zenosim

if TYPE_CHECKING:
    import numpy.typing as npt
    import pandas

__all__ = ["Model", "ModelError", "Run", "SweepTable", "run", "sweep", "__version__"]


class SweepTable(dict):
    """The table of a sweep: column name → numpy array, one row per run.

    The columns are, in order (the names of ``zenosim sweep``'s CSV, without its ``index``):
    each swept name (the values the run used); ``status`` (``Run.status``'s words, or
    ``"invalid"`` for a point the model refuses); ``impacts``; ``t_zeno`` and ``t_switch`` of
    the first Zeno point (NaN where there is none); ``t_final``; ``final_<coordinate>`` for each
    coordinate and ``final_<coordinate>_dot`` for each velocity, the final state; ``message``,
    what happened in a sentence.
    """

    __slots__ = ()

    @property
    def rows(self) -> int:
        """The number of runs."""
        return len(next(iter(self.values()))) if self else 0

    def to_pandas(self) -> "pandas.DataFrame":
        """The table as a ``pandas.DataFrame`` (pandas is needed for this alone)."""
        try:
            import pandas
        except ImportError as error:  # pragma: no cover - depends on the environment
            raise ImportError(
                "SweepTable.to_pandas() needs pandas: pip install pandas "
                "(the table itself is a dict of numpy arrays)"
            ) from error
        return pandas.DataFrame(dict(self))

    def __repr__(self) -> str:
        return f"zenosim.SweepTable(rows={self.rows}, columns={list(self)})"


def sweep(
    model: Union[Model, str, "os.PathLike[str]"],
    values: Mapping[str, Union[Sequence[float], "npt.ArrayLike"]],
    *,
    t_end: float | None = None,
    zeno: Union[Literal["auto", "off"], float, None] = None,
    rtol: float | None = None,
    atol: float | None = None,
    product: bool = True,
    workers: int | None = None,
) -> SweepTable:
    """Runs ``model`` once for each combination of ``values``, in parallel, keeping no trajectory.

    ``model`` is a :class:`Model` or the path of a model file. ``values`` maps parameter or
    initial-value names to sequences of numbers, combined as a Cartesian product, the last name
    varying fastest (``product=True``), or zipped, all of one length (``product=False``).
    ``t_end``, ``zeno``, ``rtol`` and ``atol`` are as in :func:`run`. ``workers`` is the number
    of threads (default: one per core). Returns a :class:`SweepTable`, one row per run in the
    order of the points.

    A point whose values the model refuses (a restitution of 1.5) is a row of status
    ``"invalid"``, its message saying why; a run that fails is a row of status ``"failed"``.
    The GIL is released while the runs go on; Ctrl-C stops them (the runs under way at their
    next step) and raises ``KeyboardInterrupt``.
    """
    columns = _zenosim.sweep(
        model,
        values,
        t_end=t_end,
        zeno=zeno,
        rtol=rtol,
        atol=atol,
        product=product,
        workers=workers,
    )
    return SweepTable(columns)
