"""The native part of the zenosim package: import ``zenosim``, not this module."""

from __future__ import annotations

import os
from typing import Any, Literal, Mapping, Sequence, Union, final

import numpy as np
import numpy.typing as npt

__all__ = ["Model", "Run", "run", "sweep", "ModelError", "__version__"]

__version__: str

_PathLike = Union[str, "os.PathLike[str]"]
_Zeno = Union[Literal["auto", "off"], float, None]
_Value = Union[float, int, str]

class ModelError(Exception):
    """A model file (or an override of it) that zenosim refuses.

    ``str(error)`` is the command line's message: the file, the line and column or the key,
    what is wrong, the line with a caret under the place, and what to do.
    """

    file: str | None
    """The file, as it was named (``"<string>"`` for :meth:`Model.from_toml`)."""
    line: int | None
    """The 1-based line, where the mistake has a place in the file."""
    column: int | None
    """The 1-based column, in characters, where the mistake has a place in the file."""
    key: str | None
    """The key path (``"constraint[1].restitution"``), the missing key, or the name an
    override sets; None for a syntax error or the file as a whole."""

@final
class Model:
    """A hybrid Lagrangian read from a model file (TOML) and checked.

    Models pickle (their text is sent, and read again), so they can be sent to other processes.
    """

    @staticmethod
    def from_file(path: _PathLike) -> Model:
        """Reads and checks the model file at ``path``.

        Raises :class:`ModelError` for a model that zenosim refuses (also a file over 1 MiB or
        not UTF-8), and ``OSError`` (``FileNotFoundError``, ...) for a file that cannot be read.
        """
    @staticmethod
    def from_toml(text: str) -> Model:
        """Reads and checks a model from the text of a model file (named ``"<string>"`` in
        messages). Raises :class:`ModelError`."""
    @property
    def name(self) -> str:
        """The model's ``name``."""
    @property
    def description(self) -> str | None:
        """The model's ``description``, or None."""
    @property
    def file(self) -> str:
        """The file the model was read from (``"<string>"`` for :meth:`from_toml`)."""
    @property
    def coordinates(self) -> list[str]:
        """The coordinates' names, in order."""
    @property
    def velocities(self) -> list[str]:
        """The velocities' names, ``<coordinate>_dot``, in order."""
    @property
    def parameters(self) -> dict[str, float]:
        """The parameters and their values, in the file's order."""
    @property
    def initial(self) -> dict[str, float]:
        """The initial value of each coordinate and velocity, by name."""
    @property
    def constraints(self) -> list[str]:
        """The constraints' names, in order."""

@final
class Run:
    """The record of one run: what ``zenosim run`` writes in trajectory.csv and summary.json.

    The arrays have one row per accepted step (or per ``dt``) and two rows at the same ``t``
    around every event, the states just before and just after it.
    """

    @property
    def status(self) -> Literal["finished", "zeno_stalled", "failed"]:
        """How the run ended: ``"finished"``, ``"zeno_stalled"`` (stopped at a Zeno point with
        ``zeno="off"``) or ``"failed"`` (what was computed up to then is kept)."""
    @property
    def message(self) -> str:
        """What happened, in a sentence (for a failure: when and why)."""
    @property
    def t(self) -> npt.NDArray[np.float64]:
        """The times of the rows, shape (rows,)."""
    @property
    def q(self) -> npt.NDArray[np.float64]:
        """The coordinates, shape (rows, coordinates)."""
    @property
    def q_dot(self) -> npt.NDArray[np.float64]:
        """The velocities, shape (rows, coordinates)."""
    @property
    def h(self) -> npt.NDArray[np.float64]:
        """Each constraint's ``h(t, q)``, shape (rows, constraints)."""
    @property
    def multipliers(self) -> npt.NDArray[np.float64]:
        """Each constraint's multiplier ``λ`` (trajectory.csv's ``lambda_<name>``: the contact
        force is ``−Aᵀλ``, 0 where the constraint is not held), shape (rows, constraints)."""
    @property
    def friction(self) -> npt.NDArray[np.float64]:
        """The tangential forces ``fₜ`` of the constraints with friction (trajectory.csv's
        ``f_<name>``, along increasing slip, and ``f2_<name>`` for the second component of a
        contact in space), shape (rows, len(friction_columns))."""
    @property
    def friction_constraints(self) -> list[str]:
        """The names of the constraints with friction."""
    @property
    def friction_columns(self) -> list[str]:
        """The names of the columns of ``friction``: ``f_<name>`` for each constraint with
        friction, followed by ``f2_<name>`` for a contact in space."""
    @property
    def energy(self) -> npt.NDArray[np.float64]:
        """The energy ``q̇ᵀ ∂L/∂q̇ − L`` of each row, shape (rows,)."""
    @property
    def balance(self) -> dict[str, npt.NDArray[np.float64]]:
        """The energy balance from the start to each row, each shape (rows,): ``work_forces``,
        ``work_drive``, ``work_constraints``, ``impact_loss``, ``work_friction``, with
        ``energy − energy[0] = work_forces + work_drive + work_constraints + work_friction −
        impact_loss`` to the integration tolerance (docs/output.md)."""
    @property
    def energy_balance(self) -> dict[str, Any]:
        """The run's energy balance, as summary.json's ``energy_balance``."""
    @property
    def mode(self) -> list[str]:
        """Each row's mode as trajectory.csv writes it: ``"free"``, or ``"constrained:"`` and
        the names of the constraints held joined by ``+``, then for a model with friction
        ``;stick:`` and ``;slip:`` and the held contacts that stick or slip (each list only
        where not empty)."""
    @property
    def events(self) -> list[dict[str, Any]]:
        """Every event, as summary.json's ``events``: ``kind`` (``impact``, ``zeno``,
        ``liftoff``), ``t``, ``constraint``, ``contacts``, ``impulses``, ``before``,
        ``after`` (without ``q`` where it is ``before``'s, summary.json's schema 4)."""
    @property
    def zeno(self) -> list[dict[str, Any]]:
        """Every Zeno point, as summary.json's ``zeno``: ``constraint``, ``constraints``,
        ``kind``, ``t_switch``, ``t_zeno`` (the estimate of τ∞), ``impacts``, ``ratio``,
        ``event`` (the index in ``events`` of its ``zeno`` event, whose ``after`` is the state
        after R∞), and ``point`` only for a point without an event (a stall)."""
    @property
    def final(self) -> dict[str, Any]:
        """Where the run ended, as summary.json's ``final``: ``t``, ``mode``, ``active``,
        ``q``, ``q_dot``, ``energy``."""
    @property
    def coordinates(self) -> list[str]:
        """The coordinates' names (the columns of ``q`` and ``q_dot``)."""
    @property
    def constraints(self) -> list[str]:
        """The constraints' names (the columns of ``h``)."""

def run(
    model: Model | _PathLike,
    *,
    t_end: float | None = None,
    zeno: _Zeno = None,
    rtol: float | None = None,
    atol: float | None = None,
    dt: float | None = None,
    set: Mapping[str, _Value] | None = None,
    max_events: int | None = None,
    max_steps: int | None = None,
    max_output: int | None = None,
) -> Run:
    """Runs ``model`` (a :class:`Model` or the path of a model file) once, keeping its
    trajectory.

    Each setting left None is the model file's (its ``[simulation]``, else zenosim's default):
    ``t_end``; ``zeno``, ``"auto"`` (switch to the constrained motion at a Zeno point), ``"off"``
    (stop there) or a number ε (the paper's rule ``|h| ≤ ε, |ḣ| ≤ ε``); the tolerances ``rtol``
    and ``atol``; ``dt``, rows every ``dt`` on a uniform grid instead of at every step. ``set``
    changes parameters or initial values: numbers, or formulas as the file writes them.

    The limits: ``max_events`` (100 000 by default) and ``max_steps`` (10⁷), which the model
    file's ``[simulation]`` may lower but never raise, so that a file cannot make a run hold
    more than its caller allows; ``max_output``, the bytes the record may take (1 GiB, as the
    command line's ``--max-output``). A run that reaches one stops with ``status`` ``"failed"``,
    keeping what it computed, and its ``message`` says which and what to do.

    The GIL is released while simulating. Ctrl-C raises ``KeyboardInterrupt`` within about
    50 ms. A run that fails is no exception: its ``status`` says so. Raises :class:`ModelError`
    for a model (or an override) that zenosim refuses, ``ValueError`` and ``TypeError`` for bad
    arguments.
    """

def sweep(
    model: Model | _PathLike,
    values: Mapping[str, Sequence[float] | npt.ArrayLike],
    *,
    t_end: float | None = None,
    zeno: _Zeno = None,
    rtol: float | None = None,
    atol: float | None = None,
    product: bool = True,
    workers: int | None = None,
) -> dict[str, npt.NDArray[Any]]:
    """The columns of :func:`zenosim.sweep`'s table (use ``zenosim.sweep``)."""
