"""debris from Python: the cohesive DEM and PeriDEM runs of the executables, driven step by step.

    import debris
    sim = debris.Dem("scenarios/dem/hcp_wall_load.yaml", output="out/py", quiet=True)
    sim.run(100)                          # 100 steps: thermo.csv, frames, checks as debris_dem does
    print(sim.thermo()["kinetic_energy"])
    vx = sim.state.vx                     # a view of the live column (numpy, no copy), read-only
    with sim.edit() as state:             # writing goes through an edit
        state.vx[:] = 0.0                 # the forces of this step are evaluated again at its end
    sim.run()                             # the rest of the plan, then the closing report and pass table

A run is made from a YAML file or a dict with the same keys (units as strings, "73 GPa"), or from a
checkpoint (restart=...). It writes the executable's outputs (thermo.csv, dump, HDF5/XDMF, checkpoints) into
its output directory, bit for bit the same. Bad input raises InputError with the executable's message; a run
that stops (a failed health check, an output that cannot be written) raises RunStopped naming the step and
the last good checkpoint.

The state is the columns of the simulation's structure of arrays (debris.columns("dem"), ("peridem")). A
view (sim.state.x) reads the live memory each time it is used; np.asarray(view) is that memory itself, with
no copy, valid until the next step or edit. DEM particles are re-sorted in memory at neighbour rebuilds: a
view made before a re-sort raises StaleViewError instead of reading particles that moved elsewhere (take
`sim.state` again; `id` follows a particle across re-sorts).
"""

import contextlib
import operator
import os
import sys

from . import _build


def _wrong_interpreter(problem):
    """ImportError saying which interpreter this build of debris is for, and how to run it with that one."""
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    this = sys.executable or "this interpreter"
    return ImportError(
        f"debris: {problem}. This debris was built for {_build.executable} (Python {_build.version}); this is "
        f"{this} (Python {sys.version.split()[0]}). Run it with the interpreter it was built for: "
        f"PYTHONPATH={here} {_build.executable} your_script.py; or configure the build for this one: "
        f"cmake -S <debris> -B build -DPython3_EXECUTABLE={this} (it needs numpy and pybind11 there)")


if sys.version_info[:2] != tuple(int(v) for v in _build.version.split(".")[:2]):
    raise _wrong_interpreter(f"its compiled part is for Python {'.'.join(_build.version.split('.')[:2])}")
try:
    import numpy as np
    from numpy.lib.mixins import NDArrayOperatorsMixin
except ImportError as e:
    raise _wrong_interpreter(f"numpy cannot be imported here ({e})") from e
try:
    from . import _debris
except ImportError as e:
    raise _wrong_interpreter(f"its compiled part _debris cannot be loaded here ({e})") from e
from ._debris import InputError, RunStopped, StaleViewError, load_input, offload_build, yaml_from_dict

__all__ = ["Dem", "Peridem", "InputError", "RunStopped", "StaleViewError", "columns", "load_input",
           "yaml_from_dict", "offload_build"]


def columns(model):
    """The state's column names of a model ("dem" or "peridem"), in storage order."""
    return list(_debris.columns(model))


class Column(NDArrayOperatorsMixin):
    """One column of a run's live state. Every use checks that the storage order is still the one the view
    was made for, then reads the simulation's memory (brought to the host first in offload builds).
    Arithmetic and numpy functions work on it as on an array and return new arrays."""

    def __init__(self, sim, name, edit=None):
        self._sim = sim
        self._name = name
        self._edit = edit  # the edit it was made in (writable), or None (read-only)
        self._generation = sim._run.generation()

    def _array(self):
        sim = self._sim
        if sim._run.generation() != self._generation:
            raise StaleViewError(
                f"the view of '{self._name}' was made before the particles were re-sorted in memory "
                f"(step {sim.step}); take sim.state.{self._name} again (the 'id' column follows a particle)")
        writable = self._edit is not None
        if writable and sim._edit is not self._edit:
            raise StaleViewError(f"the writable view of '{self._name}' belongs to an edit that has ended")
        return sim._run.column(self._name, writable, sim)

    def numpy(self):
        """The column itself as a numpy array (no copy), valid until the next step or edit."""
        return self._array()

    def copy(self):
        return self._array().copy()

    def __array__(self, dtype=None, copy=None):
        a = self._array()
        if dtype is not None and np.dtype(dtype) != a.dtype:
            return a.astype(dtype)
        return a.copy() if copy else a

    def __array_ufunc__(self, ufunc, method, *inputs, **kwargs):
        inputs = tuple(x._array() if isinstance(x, Column) else x for x in inputs)
        if "out" in kwargs:
            kwargs["out"] = tuple(x._array() if isinstance(x, Column) else x for x in kwargs["out"])
        return getattr(ufunc, method)(*inputs, **kwargs)

    def __getitem__(self, key):
        out = self._array()[key]
        # A slice of the column would be a view that outlives this check: hand out a copy.
        return out.copy() if isinstance(out, np.ndarray) else out

    def __setitem__(self, key, value):
        if self._edit is None:
            raise ValueError(f"'{self._name}' is read-only here: write inside `with sim.edit() as state:`")
        self._array()[key] = value

    def __len__(self):
        return len(self._array())

    def __iter__(self):
        return iter(self._array().copy())

    @property
    def shape(self):
        return self._array().shape

    @property
    def dtype(self):
        return self._array().dtype

    @property
    def name(self):
        return self._name

    def __repr__(self):
        return f"debris column '{self._name}' {self._array()!r}"


class State:
    """The columns of a run's state as attributes (sim.state.x, sim.state.radius, ...), and grouped:
    positions, velocities, forces (each a tuple of the x, y, z columns)."""

    def __init__(self, sim, edit=None):
        object.__setattr__(self, "_sim", sim)
        object.__setattr__(self, "_edit", edit)
        object.__setattr__(self, "_names", columns(sim._kind))

    def __getattr__(self, name):
        if name not in self._names:
            raise AttributeError(f"'{name}': no such column (columns: {', '.join(self._names)})")
        edit = self._edit
        if edit is not None and name not in edit.saved:
            # Kept until the edit ends, so that an edit refused by the checks leaves the state as it was.
            edit.saved[name] = np.array(self._sim._run.column(name, False, self._sim), copy=True)
        return Column(self._sim, name, edit)

    def __setattr__(self, name, value):
        getattr(self, name)[...] = value

    def __dir__(self):
        return list(self._names) + ["positions", "velocities", "forces"]

    @property
    def positions(self):
        return (self.x, self.y, self.z)

    @property
    def velocities(self):
        return (self.vx, self.vy, self.vz)

    @property
    def forces(self):
        return (self.fx, self.fy, self.fz)


class _Edit:
    def __init__(self):
        self.saved = {}  # each column taken in the edit, as it was before: {name: copy}


class _Simulation:
    _kind = None
    _position_columns = ("x", "y", "z")

    def __init__(self, input=None, *, restart=None, output=None, threads=0, quiet=False, base_directory=None):
        """`input`: a YAML file, or a dict with its keys; `restart`: a checkpoint to continue from (with an
        input, its stages, run.steps and output); `output`: the output directory (overrides
        output.directory); `threads`: host threads (0: run.threads, else OMP_NUM_THREADS, else tuned while
        stepping); `quiet`: print nothing; `base_directory`: where a dict's relative paths start (default:
        the current directory)."""
        values, path = None, ""
        if isinstance(input, dict):
            values = input
        elif input is not None:
            path = os.fspath(input)
        self._edit = None
        self._run = _debris._Run(self._kind, path, values, os.fspath(restart) if restart else "",
                                 os.fspath(output) if output else "", os.fspath(base_directory or ""),
                                 int(threads), bool(quiet))

    # Where the run is.
    @property
    def step(self):
        return self._run.step

    @property
    def time(self):
        return self._run.time

    @property
    def dt(self):
        return self._run.dt

    @property
    def last_step(self):
        """The plan's last step (run.steps, or the end of the stages)."""
        return self._run.last_step

    @property
    def done(self):
        return self._run.done

    @property
    def finished(self):
        return self._run.finished

    @property
    def directory(self):
        return self._run.directory

    @property
    def input_text(self):
        """The input as the run read it (a dict's YAML text), kept in every checkpoint."""
        return self._run.input_text

    @property
    def stages(self):
        """[{name, start, end}] on the step axis."""
        return self._run.stages()

    @property
    def progress(self):
        """{first_step, step, last_step, fraction, seconds, steps_per_second, seconds_left}"""
        return self._run.progress()

    # Stepping.
    def run(self, steps=None, *, finish=True):
        """Makes `steps` steps (None: to the plan's end), with the executable's outputs and checks at each.
        `steps` is a whole number from 0 to the steps left in the plan (last_step - step): a count past the
        plan's end is refused (ValueError), as the plan (run.steps, the stages) is what sets the outputs and
        the closing report. At the plan's end the run is finished (closing report and pass table) unless
        finish=False. Returns self."""
        return self._advance(lambda: self._run.advance(self._steps_to_make(steps)), finish)

    def _steps_to_make(self, steps):
        left = self._run.last_step - self._run.step
        if steps is None:
            return left
        if isinstance(steps, bool):
            raise TypeError(f"run(steps={steps!r}): steps is a count of steps (an int), not a bool")
        try:
            n = operator.index(steps)
        except TypeError:
            raise TypeError(f"run(steps={steps!r}): steps is a whole number of steps (an int), not a "
                            f"{type(steps).__name__}") from None
        if n < 0:
            raise ValueError(f"run(steps={n}): steps must be >= 0")
        if n > left:
            raise ValueError(f"run(steps={n}) at step {self._run.step}: the plan ends at step {self._run.last_step}, "
                             f"{left} steps from here; give at most {left} (run() runs to the end), or a longer "
                             f"plan (run.steps, the stages)")
        return n

    def run_stage(self, *, finish=True):
        """Runs to the start of the next stage (its changes made) or to the end. Returns self."""
        return self._advance(self._run.advance_stage, finish)

    def _advance(self, advance, finish):
        self._check_no_edit()
        advance()
        if finish and self._run.done and not self._run.finished:
            self._run.finish()
        return self

    def finish(self):
        """The executable's end of a run: closing report and pass table (printed unless quiet)."""
        self._run.finish()
        return self

    @property
    def report(self):
        """What the end of the run reported before the pass table (a verdict, pictures drawn); '' before."""
        return self._run.report

    def pass_table(self):
        """{rows: [{name, seconds, share, note}], total, stepping, steps, items_steps_per_second,
        bytes_per_step}: the table the run prints at its end, at any time."""
        return self._run.pass_table()

    # Values.
    def thermo_columns(self):
        return list(self._run.thermo_columns())

    def thermo(self):
        """The thermo row of the current step as a dict (the columns of thermo.csv)."""
        row = dict(zip(self._run.thermo_columns(), self._run.thermo_row()))
        row["step"] = int(row["step"])
        return row

    def checkpoint(self, path=None):
        """Writes a checkpoint (the executables' format: either can restart from it); returns its path."""
        self._check_no_edit()
        return self._run.checkpoint(os.fspath(path) if path else "")

    # State.
    @property
    def state(self):
        """The live columns, read-only (see Column)."""
        return State(self)

    @contextlib.contextmanager
    def edit(self):
        """`with sim.edit() as state:` the columns, writable. At the end the host copy is marked changed
        (offload builds send it to the device before the next kernel), the neighbour or contact list is
        rebuilt if positions were written, and this step's forces are evaluated again, as a stage's changes
        are. What was written is checked as the input's values are (a radius > 0, ids unique, every value
        finite, ...): a bad value raises InputError naming the column, the value and the item, and every
        column taken in the edit is put back as it was."""
        self._check_no_edit()
        edit = _Edit()
        content = self._run.begin_edit()  # what the edit changes of it is work done on the system
        self._edit = edit
        try:
            yield State(self, edit)
        finally:
            self._edit = None
            written = sorted(edit.saved)
            try:
                self._run.end_edit(written, bool(set(written) & set(self._position_columns)), content)
            except InputError:
                for name, before in edit.saved.items():
                    self._run.column(name, True, self)[...] = before
                raise

    def _check_no_edit(self):
        if self._edit is not None:
            raise RuntimeError("an edit is open: end the `with sim.edit()` block first")


class Dem(_Simulation):
    """A cohesive DEM run (debris_dem): from a YAML file or a dict of its keys, or a checkpoint."""
    _kind = "dem"

    @property
    def groups(self):
        """{name: {motion, velocity, external_force, count, mass, reaction, displacement}}"""
        return {g.pop("name"): g for g in self._run.dem_groups()}

    @property
    def label_names(self):
        return list(self._run.dem_label_names())

    def energy(self):
        """The energy balance since the start, as thermo.csv's energy columns: {work_in, work_drives (per
        group), work_stages (stages' and edits' changes), kinetic_energy and _start, elastic_energy and _start,
        dissipated_normal, dissipated_tangential, dissipated_sliding, dissipated_global, tangential_work,
        residual}; work_in = the kinetic and elastic changes + the four dissipated + residual. None when
        output.energy is false."""
        return self._run.dem_energy()

    def diagnostics(self):
        """{kinetic_energy, elastic_energy, max_overlap, interacting_pairs, rebuilds, layout_generation}"""
        return self._run.dem_diagnostics()

    def wear(self):
        """The wear analysis (inputs with `wear:`), or None: {verdict, report, detection_index, samples,
        last}, each sample a dict of the wear.csv columns with its verdicts by name."""
        return self._run.dem_wear()

    def surfaces(self):
        """The wear census (inputs with `surfaces:`), or None: {report, samples}, each sample a dict of the
        surfaces.csv columns with its `histogram` (surfaces_histogram.csv's rows of that sample)."""
        return self._run.dem_surfaces()

    def resort(self):
        """A neighbour rebuild now, with its re-sort in memory (views made before it go stale)."""
        self._check_no_edit()
        self._run.dem_rebuild()


class Peridem(_Simulation):
    """A PeriDEM run (debris_peridem): from a YAML file or a dict of its keys, or a checkpoint."""
    _kind = "peridem"

    @property
    def grains(self):
        """{name: {kind, nodes (begin, end), volume, centre, velocity, reaction}}, walls included; the
        centre and velocity are the volume-weighted means of the nodes, the reaction a wall's contact force."""
        return {g.pop("name"): g for g in self._run.pd_grains()}

    def wall_reactions(self):
        """{wall name: (fx, fy, fz)}: the contact force on each wall this step."""
        return {name: g["reaction"] for name, g in self.grains.items() if g["kind"] == "wall"}

    def diagnostics(self):
        """{kinetic_energy, bond_energy, contact_energy, max_damage, broken_bonds, contact_pairs, momentum,
        touching_pairs, deepest_penetration}"""
        return self._run.pd_diagnostics()

    def touching_pairs(self):
        """Node pairs closer than their contact radius R_c now, each once (cheap: no energies)."""
        return self._run.pd_touching_pairs()

    @property
    def broken_bonds(self):
        """Bonds broken since the start (a counter: no sweep over the bonds)."""
        return self._run.pd_broken_bonds()

    def displacements(self):
        """Each node's displacement from its reference position, a (3, n) array (a new array)."""
        s = self.state
        return np.stack([np.asarray(s.x) - np.asarray(s.x0), np.asarray(s.y) - np.asarray(s.y0),
                         np.asarray(s.z) - np.asarray(s.z0)])
