"""Junction demonstrations driven by SUMO: the realistic source, same shape as the native expert.

:func:`sumo_expert_episodes` returns ``list[list[(JunctionState, action)]]`` exactly like
:meth:`TrafficJunction.expert_episode`, so a learner cannot tell which source it was given;
:func:`sumo_demonstrations` returns the same episodes with a report (pairs SUMO's behaviour
breaks relative to our ground truth, dropped vehicles, timings). SUMO (``eclipse-sumo`` and
``traci`` from PyPI, the ``sumo`` extra) is optional: without it both raise
:class:`MissingDependencyError` with the install hint. The native model stays the fast default.

How a SUMO drive becomes grid pairs, and why:

* **Network.** One node per arm end and the junction node, written as plain XML and compiled by
  the ``netconvert`` of the installed package (no download, no SUMO_HOME needed). ``lights``:
  two-way single-lane roads and SUMO's own static signal program (two greens, each followed by
  yellow, no all-red); ``priority``: the one-way roads of ``ONE_WAY_FLOW`` into a
  ``right_before_left`` node, so SUMO's junction model decides who yields. U-turns are not
  built because the native expert never leaves by the arm it came in on.
* **Cells follow the lanes, not metres on a map.** A vehicle on an approach lane is ``k`` cells
  out, counted by its front bumper's distance to the stop line in steps of ``cell_length``;
  on an exit lane by its distance from the junction; on any SUMO-internal lane (inside the
  junction polygon) it is on the junction cell. So "the junction cell" means exactly the area
  SUMO's junction logic guards, and a car waiting at the stop line is in the before-junction
  cell, never half inside the junction. The roads run ``margin`` metres past the grid so
  vehicles are inserted and removed out of sight.
* **One grid step is ``cell_length / speed`` seconds**, so a car at the speed limit advances one
  cell per step. SUMO runs at ``sim_step`` (a fraction of that) so no cell is jumped over; a
  grid step with no change of cell is ``zero``, and every change of cell is one move (several
  in one grid step if the car was fast). If a car ever did skip a cell, the missing moves are
  filled in along the road, so consecutive cells are always neighbours.
* **Observations are taken when the move happens.** A move is paired with the light phase SUMO
  used for that simulation step (the state read right after the step: SUMO switches signals
  before it moves vehicles, and reading the light one step earlier turned a car that starts on
  green into a red-light breach in our trials); a ``zero`` step with what the car saw at the
  start of the grid step. The phase is the model's: ``tls0`` when the north/south approaches are all red,
  ``tls1`` when the east/west ones are (``RED_ARMS``); yellow counts as not red, since the
  other approaches are still red and a car that cannot stop may cross, and a moment where
  both or neither are red (none in this program) keeps the previous phase.
* **car_on_right only at the stop line.** The model makes every non-``zero`` action with
  ``car_on_right`` a violation wherever the car is, so the flag is set only where it matters:
  the ego is in the before-junction cell of its approach and a vehicle is on the approach to its
  right within ``right_distance`` of the stop line. Further back the ego simply drives on.
* **Nothing is hidden.** Every pair is checked with ``model.is_allowed``; pairs SUMO's driver
  model produces against our rules are kept in the episodes and counted by rule in the report
  (and announced by a warning from :func:`sumo_expert_episodes`). Ego vehicles that SUMO
  teleports (a jam) or that do not finish in time are dropped, counted, and replaced.

All egos of one call drive in one simulation, among each other and Poisson background traffic,
with ``--seed``; all files live in a temporary directory.
"""

from __future__ import annotations

import contextlib
import io
import os
import subprocess
import tempfile
import time
import warnings
from collections import Counter, deque
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from symlearn.envs.traffic_model import (
    ARMS,
    ONE_WAY_EXITS,
    ONE_WAY_FLOW,
    OPPOSITE,
    RED_ARMS,
    STEP,
    Cell,
    JunctionState,
    TrafficJunction,
)
from symlearn.errors import ModelError
from symlearn.optional import require
from symlearn.progress import progress

Pair = tuple[JunctionState, str]

_PURPOSE = "SUMO junction demonstrations"
_JUNCTION = "C"
#: The arm approaching from the right of a car heading in each direction (right-hand traffic).
_RIGHT_OF_HEADING: dict[str, str] = {"east": "south", "south": "west", "west": "north", "north": "east"}
_MOVE_OF_STEP: dict[Cell, str] = {delta: name for name, delta in STEP.items()}


@dataclass(frozen=True)
class SumoSettings:
    """Geometry, traffic and timing of the simulated junction (defaults: a small town junction)."""

    cell_length: float = 20.0  #: metres of road per grid cell
    speed: float = 10.0  #: speed limit in m/s; one grid step = cell_length / speed seconds
    sim_step: float = 0.25  #: SUMO step in seconds (a divisor of the grid step)
    margin: float = 60.0  #: road beyond the grid where vehicles appear and vanish
    background_rate: float = 0.04  #: background vehicles per second on each approach
    ego_interval: float = 6.0  #: mean seconds between ego departures
    green: float = 12.0  #: seconds of green per direction (lights)
    yellow: float = 3.0  #: seconds of yellow (lights)
    right_distance: float = 25.0  #: metres from the stop line within which a car on the right counts
    patience: float = 300.0  #: seconds after its departure before an unfinished ego is dropped

    @property
    def grid_step(self) -> float:
        return self.cell_length / self.speed

    @property
    def steps_per_cell(self) -> int:
        ratio = self.grid_step / self.sim_step
        if ratio < 1 or abs(ratio - round(ratio)) > 1e-6:
            raise ModelError(f"sim_step {self.sim_step} s must divide the grid step {self.grid_step} s "
                             "(cell_length / speed)")
        return int(round(ratio))


@dataclass(frozen=True)
class Violation:
    """A pair SUMO produced that our ground truth forbids."""

    episode: int
    step: int
    state: JunctionState
    action: str
    rules: tuple[str, ...]


@dataclass
class SumoDemonstrations:
    """Episodes from SUMO and what happened on the way."""

    variant: str
    episodes: list[list[Pair]]
    violations: list[Violation]
    dropped: Counter = field(default_factory=Counter)  #: reason -> ego vehicles given up
    seconds: float = 0.0  #: wall-clock time, network building included
    simulated_seconds: float = 0.0

    @property
    def n_pairs(self) -> int:
        return sum(len(e) for e in self.episodes)

    @property
    def allowed_fraction(self) -> float:
        """Share of pairs the ground truth allows (1.0 when SUMO never broke a rule)."""
        return 1.0 - len(self.violations) / max(self.n_pairs, 1)

    @property
    def violation_counts(self) -> Counter:
        """Broken ground-truth rule -> number of pairs."""
        return Counter(rule for v in self.violations for rule in v.rules)

    @property
    def episodes_per_second(self) -> float:
        return len(self.episodes) / self.seconds if self.seconds > 0 else float("inf")

    def summary(self) -> dict[str, object]:
        return {"variant": self.variant, "episodes": len(self.episodes), "pairs": self.n_pairs,
                "allowed_fraction": self.allowed_fraction, "violations": dict(self.violation_counts),
                "dropped": dict(self.dropped), "seconds": self.seconds,
                "simulated_seconds": self.simulated_seconds, "episodes_per_second": self.episodes_per_second}


def sumo_expert_episodes(model: TrafficJunction, n_episodes: int, seed: int,
                         settings: SumoSettings | None = None, max_steps: int | None = None) -> list[list[Pair]]:
    """``n_episodes`` drives of SUMO-controlled cars, as ``(JunctionState, action)`` lists.

    Pairs that break the ground truth are kept and announced with a warning; use
    :func:`sumo_demonstrations` for the full report.
    """
    result = sumo_demonstrations(model, n_episodes, seed, settings=settings, max_steps=max_steps)
    if result.violations:
        counts = ", ".join(f"{rule}: {n}" for rule, n in sorted(result.violation_counts.items()))
        warnings.warn(f"{len(result.violations)} of {result.n_pairs} SUMO pairs break the {model.variant} "
                      f"ground truth ({counts})", stacklevel=2)
    return result.episodes


def sumo_demonstrations(model: TrafficJunction, n_episodes: int, seed: int,
                        settings: SumoSettings | None = None, max_steps: int | None = None) -> SumoDemonstrations:
    """Simulate ``n_episodes`` ego cars through the junction in SUMO and discretise their drives.

    ``max_steps`` cuts an episode (as the native expert does); ``None`` keeps whole drives.
    """
    require("sumo", _PURPOSE)
    if n_episodes < 0:
        raise ModelError(f"n_episodes must be >= 0, got {n_episodes}")
    settings = settings or SumoSettings()
    settings.steps_per_cell  # noqa: B018 - validates the timing before anything runs
    started = time.perf_counter()
    result = SumoDemonstrations(model.variant, [], [])
    if n_episodes == 0:
        return result
    with tempfile.TemporaryDirectory(prefix="symlearn-sumo-") as tmp:
        rng = np.random.default_rng(seed)
        scene = _Scene(model, settings, Path(tmp))
        scene.build_network()
        scene.write_routes(n_episodes, rng)
        run = _Run(scene, n_episodes, seed, max_steps, result)
        for _ in progress(run.egos(), total=n_episodes, desc=f"SUMO {model.variant}", unit="episode"):
            pass
    for index, episode in enumerate(result.episodes):
        for step, (state, action) in enumerate(episode):
            model.state_index(state)  # every observation must be a state of the model
            broken = model.violations(state, action)
            if broken:
                result.violations.append(Violation(index, step, state, action, tuple(broken)))
    result.seconds = time.perf_counter() - started
    return result


# --- the scene: network and routes -------------------------------------------------------------
class _Scene:
    def __init__(self, model: TrafficJunction, settings: SumoSettings, folder: Path) -> None:
        self.model = model
        self.settings = settings
        self.folder = folder
        jx, jy = model.junction
        #: grid cells on each arm
        self.cells = {"north": model.size - jy, "south": jy - 1, "east": model.size - jx, "west": jx - 1}
        if model.one_way:
            self.approaches = [a for a in ARMS if ONE_WAY_FLOW[a] == OPPOSITE[a]]
            self.exits = sorted(ONE_WAY_EXITS)
        else:
            self.approaches = list(ARMS)
            self.exits = list(ARMS)
        self.net = folder / "junction.net.xml"
        self.routes = folder / "junction.rou.xml"

    def routes_from(self, arm: str) -> list[str]:
        return [e for e in self.exits if e != arm]

    def build_network(self) -> None:
        s = self.settings
        node_type = "traffic_light" if self.model.has_lights else "right_before_left"
        nodes = [f'  <node id="{_JUNCTION}" x="0" y="0" type="{node_type}"/>']
        edges = []
        for arm in ARMS:
            if arm not in self.approaches and arm not in self.exits:
                continue
            dx, dy = STEP[arm]
            reach = self.cells[arm] * s.cell_length + s.margin + 10.0  # 10 m: room for the junction
            nodes.append(f'  <node id="{arm}" x="{dx * reach:.2f}" y="{dy * reach:.2f}"/>')
            if arm in self.approaches:
                edges.append(f'  <edge id="in_{arm}" from="{arm}" to="{_JUNCTION}" numLanes="1" speed="{s.speed}"/>')
            if arm in self.exits:
                edges.append(f'  <edge id="out_{arm}" from="{_JUNCTION}" to="{arm}" numLanes="1" speed="{s.speed}"/>')
        (self.folder / "junction.nod.xml").write_text("<nodes>\n" + "\n".join(nodes) + "\n</nodes>\n")
        (self.folder / "junction.edg.xml").write_text("<edges>\n" + "\n".join(edges) + "\n</edges>\n")
        command = [_binary("netconvert"), "--node-files", "junction.nod.xml", "--edge-files", "junction.edg.xml",
                   "--output-file", self.net.name, "--no-turnarounds", "true",
                   "--offset.disable-normalization", "true", "--tls.default-type", "static",
                   "--tls.green.time", str(int(s.green)), "--tls.yellow.time", str(int(s.yellow)),
                   "--tls.allred.time", "0", "--no-warnings", "true"]
        done = subprocess.run(command, cwd=self.folder, capture_output=True, text=True, timeout=120)
        if done.returncode != 0 or not self.net.exists():
            raise ModelError(f"netconvert failed to build the {self.model.variant} junction: "
                             f"{(done.stderr or done.stdout).strip()[-500:]}")

    def write_routes(self, n_egos: int, rng: np.random.Generator) -> None:
        """Ego cars (ids ``ego<i>``) at jittered intervals, Poisson background on every approach."""
        s = self.settings
        vehicles: list[tuple[float, str, str]] = []  # (depart, id, route id)
        for i in range(n_egos):
            depart = 2.0 + s.ego_interval * (i + rng.random())
            arm = self.approaches[int(rng.integers(len(self.approaches)))]
            exits = self.routes_from(arm)
            vehicles.append((depart, f"ego{i}", f"r_{arm}_{exits[int(rng.integers(len(exits)))]}"))
        horizon = 2.0 + s.ego_interval * (n_egos + 1) + s.patience
        for arm in self.approaches:
            t, k = 0.0, 0
            while s.background_rate > 0:
                t += rng.exponential(1.0 / s.background_rate)
                if t > horizon:
                    break
                exits = self.routes_from(arm)
                vehicles.append((t, f"bg_{arm}{k}", f"r_{arm}_{exits[int(rng.integers(len(exits)))]}"))
                k += 1
        vehicles.sort()
        lines = ["<routes>", '  <vType id="car" vClass="passenger"/>']
        for arm in self.approaches:
            for goal in self.routes_from(arm):
                lines.append(f'  <route id="r_{arm}_{goal}" edges="in_{arm} out_{goal}"/>')
        for depart, vid, route in vehicles:
            lines.append(f'  <vehicle id={quoteattr(vid)} type="car" route="{route}" depart="{depart:.2f}" '
                         'departLane="best" departSpeed="max"/>')
        lines.append("</routes>")
        self.routes.write_text("\n".join(lines) + "\n")


def _binary(name: str) -> str:
    import sumo  # the eclipse-sumo wheel: SUMO_HOME is the package folder

    path = Path(sumo.SUMO_HOME) / "bin" / name
    if not path.exists():
        raise ModelError(f"the installed eclipse-sumo package has no {name} program at {path}",
                         hint="reinstall it: pip install --force-reinstall eclipse-sumo")
    return str(path)


# --- the run: simulation and discretisation ----------------------------------------------------
@dataclass
class _Ego:
    index: int
    departed_at: float
    arm: str | None = None  # approach it came in on
    cell: Cell | None = None  # current grid cell, None before it enters
    tick_start: int = 0  # simulation step at which the current grid step began
    tick_state: JunctionState | None = None
    moved: bool = False
    pairs: list[Pair] = field(default_factory=list)


class _Run:
    def __init__(self, scene: _Scene, n_episodes: int, seed: int, max_steps: int | None,
                 result: SumoDemonstrations) -> None:
        self.scene = scene
        self.model = scene.model
        self.settings = scene.settings
        self.n_episodes = n_episodes
        self.seed = seed
        self.max_steps = max_steps
        self.result = result
        self.lane_length: dict[str, float] = {}
        self.phase = 0
        self.rng = np.random.default_rng([seed, 1])  # routes of replacement egos
        self.conn = None

    def egos(self) -> Iterator[int]:
        """Run the simulation, yielding once per ego that finished or was dropped."""
        import traci
        import traci.constants as tc

        s = self.settings
        command = [_binary("sumo"), "--net-file", str(self.scene.net), "--route-files", str(self.scene.routes),
                   "--step-length", str(s.sim_step), "--seed", str(self.seed), "--no-step-log", "true",
                   "--no-warnings", "true", "--duration-log.disable", "true", "--time-to-teleport", "120",
                   "--log", str(self.scene.folder / "sumo.log")]
        label = f"symlearn-{os.getpid()}-{id(self)}"
        with contextlib.redirect_stdout(io.StringIO()):  # traci prints "Retrying..." while SUMO starts
            traci.start(command, label=label, stdout=subprocess.DEVNULL)
        self.conn = conn = traci.getConnection(label)
        try:
            yield from self._simulate(conn, tc)
        finally:
            conn.close()

    def _simulate(self, conn, tc) -> Iterator[int]:
        s, model = self.settings, self.model
        per_tick = s.steps_per_cell
        # Everything a step needs comes back with the step itself (one round trip per step).
        conn.simulation.subscribe((tc.VAR_TIME, tc.VAR_DEPARTED_VEHICLES_IDS,
                                   tc.VAR_TELEPORT_STARTING_VEHICLES_IDS, tc.VAR_MIN_EXPECTED_VEHICLES))
        reach = max(self.scene.cells.values()) * s.cell_length + s.margin + 100.0
        conn.junction.subscribeContext(_JUNCTION, tc.CMD_GET_VEHICLE_VARIABLE, reach,
                                       (tc.VAR_ROAD_ID, tc.VAR_LANE_ID, tc.VAR_LANEPOSITION))
        link_arms: list[str | None] = []
        if model.has_lights:
            conn.trafficlight.subscribe(_JUNCTION, (tc.TL_RED_YELLOW_GREEN_STATE,))
            for links in conn.trafficlight.getControlledLinks(_JUNCTION):
                link_arms.append(links[0][0].rsplit("_", 1)[0].removeprefix("in_") if links else None)
        active: dict[str, _Ego] = {}
        finished: dict[int, list[Pair]] = {}
        spare = self.n_episodes  # replacements for dropped egos
        step = 0
        while len(finished) < self.n_episodes:
            conn.simulationStep()
            step += 1
            sim = conn.simulation.getSubscriptionResults()
            now = sim[tc.VAR_TIME]
            for vid in sim[tc.VAR_DEPARTED_VEHICLES_IDS]:
                if vid.startswith("ego"):
                    active[vid] = _Ego(int(vid.removeprefix("ego").split("_")[0]), now)
            teleported = set(sim[tc.VAR_TELEPORT_STARTING_VEHICLES_IDS])
            positions = conn.junction.getContextSubscriptionResults(_JUNCTION) or {}
            if model.has_lights:
                state = conn.trafficlight.getSubscriptionResults(_JUNCTION)[tc.TL_RED_YELLOW_GREEN_STATE]
                self.phase = self._phase(state, link_arms)
            approach = self._approach_distances(positions) if model.one_way else {}
            for vid, ego in list(active.items()):
                reason = None
                if vid in teleported:
                    reason = "teleported"
                elif vid not in positions:  # arrived (or removed) without crossing the grid edge
                    reason = "vanished"
                elif now - ego.departed_at > s.patience:
                    reason = "unfinished"
                if reason is None:
                    if not self._advance(ego, positions[vid], step, per_tick, approach):
                        continue
                    finished[ego.index] = ego.pairs
                    del active[vid]
                    yield ego.index
                    continue
                self.result.dropped[reason] += 1
                del active[vid]
                if vid in positions and vid not in teleported:
                    conn.vehicle.remove(vid)
                if spare == 0:
                    raise ModelError(f"SUMO dropped too many ego cars ({dict(self.result.dropped)}); "
                                     "the settings jam the junction",
                                     hint="lower background_rate or raise ego_interval")
                spare -= 1
                arm = self.scene.approaches[int(self.rng.integers(len(self.scene.approaches)))]
                goals = self.scene.routes_from(arm)
                goal = goals[int(self.rng.integers(len(goals)))]
                conn.vehicle.add(f"ego{ego.index}_{spare}", f"r_{arm}_{goal}", typeID="car", depart="now",
                                 departLane="best", departSpeed="max")
            if not active and sim[tc.VAR_MIN_EXPECTED_VEHICLES] == 0 and len(finished) < self.n_episodes:
                raise ModelError(f"the SUMO run ended with {len(finished)} of {self.n_episodes} episodes")
        self.result.episodes = [finished[i] for i in sorted(finished)]
        self.result.simulated_seconds = now

    # --- observations ------------------------------------------------------------------------
    def _phase(self, state: str, link_arms: list[str | None]) -> int:
        red = {arm: all(c in "rus" for c, a in zip(state, link_arms, strict=False) if a == arm) for arm in ARMS}
        red_sets = [all(red[a] for a in arms) for arms in RED_ARMS]
        if red_sets[0] != red_sets[1]:
            return 0 if red_sets[0] else 1
        return self.phase  # both or neither red: keep the phase that was

    def _approach_distances(self, positions: dict) -> dict[str, float]:
        """Per approach, the distance of its first vehicle to the stop line."""
        import traci.constants as tc

        nearest: dict[str, float] = {}
        for values in positions.values():
            road = values[tc.VAR_ROAD_ID]
            if road.startswith("in_"):
                arm = road.removeprefix("in_")
                d = self._length(values[tc.VAR_LANE_ID]) - values[tc.VAR_LANEPOSITION]
                nearest[arm] = min(d, nearest.get(arm, float("inf")))
        return nearest

    def _observe(self, cell: Cell, ego: _Ego, approach: dict[str, float]) -> JunctionState:
        if self.model.has_lights:
            return JunctionState(*cell, light=self.phase)
        right = _RIGHT_OF_HEADING[OPPOSITE[ego.arm]]
        on_right = (self.model.before_junction(cell) == ego.arm
                    and approach.get(right, float("inf")) <= self.settings.right_distance)
        return JunctionState(*cell, car_on_right=on_right)

    def _length(self, lane: str) -> float:
        if lane not in self.lane_length:
            self.lane_length[lane] = self.conn.lane.getLength(lane)
        return self.lane_length[lane]

    # --- discretisation ----------------------------------------------------------------------
    def _cell(self, values: dict) -> tuple[Cell | None, str | None]:
        """Grid cell of a vehicle (None off the grid) and the arm it is on (None in the junction)."""
        import traci.constants as tc

        road = values[tc.VAR_ROAD_ID]
        if road.startswith(":"):
            return self.model.junction, None
        kind, arm = road.split("_", 1)
        if kind == "in":
            distance = self._length(values[tc.VAR_LANE_ID]) - values[tc.VAR_LANEPOSITION]
        else:
            distance = values[tc.VAR_LANEPOSITION]
        k = 1 + int(max(distance, 0.0) // self.settings.cell_length)
        if k > self.scene.cells[arm]:
            return None, arm
        dx, dy = STEP[arm]
        return (self.model.junction[0] + k * dx, self.model.junction[1] + k * dy), arm

    def _advance(self, ego: _Ego, values: dict, step: int, per_tick: int, approach: dict[str, float]) -> bool:
        """Feed one simulation step of an ego; True when its episode is complete."""
        cell, arm = self._cell(values)
        if ego.cell is None:  # not on the grid yet
            if cell is None:
                return False
            ego.arm, ego.cell, ego.tick_start, ego.moved = arm, cell, step, False
            ego.tick_state = self._observe(cell, ego, approach)
            return False
        if cell != ego.cell:
            leaving = cell is None
            target = self._exit_end(arm) if leaving else cell
            path = _road_path(self.model, ego.cell, target) + ([arm] if leaving else [])
            here = ego.cell
            for move in path:  # normally one move; more only if SUMO jumped a cell
                ego.pairs.append((self._observe(here, ego, approach), move))
                here = self.model.next_cell(here, move)
            ego.cell, ego.moved = cell, True
            if leaving or self._full(ego):
                return True
        if step - ego.tick_start >= per_tick:
            if not ego.moved:
                ego.pairs.append((ego.tick_state, "zero"))
                if self._full(ego):
                    return True
            ego.tick_start, ego.moved = step, False
            ego.tick_state = self._observe(ego.cell, ego, approach)
        return False

    def _full(self, ego: _Ego) -> bool:
        if self.max_steps is not None and len(ego.pairs) >= self.max_steps:
            del ego.pairs[self.max_steps:]
            return True
        return False

    def _exit_end(self, arm: str) -> Cell:
        dx, dy = STEP[arm]
        k = self.scene.cells[arm]
        return (self.model.junction[0] + k * dx, self.model.junction[1] + k * dy)


def _road_path(model: TrafficJunction, start: Cell, goal: Cell) -> list[str]:
    """Moves along road cells from ``start`` to ``goal`` (shortest; the road is a cross, so unique)."""
    if start == goal:
        return []
    came: dict[Cell, tuple[Cell, str] | None] = {start: None}
    queue = deque([start])
    while queue:
        cell = queue.popleft()
        for move in ARMS:
            nxt = model.next_cell(cell, move)
            if nxt is None or nxt in came or model.road_of(nxt) is None:
                continue
            came[nxt] = (cell, move)
            if nxt == goal:
                moves = []
                while came[nxt] is not None:
                    nxt, move = came[nxt]
                    moves.append(move)
                return moves[::-1]
            queue.append(nxt)
    raise ModelError(f"no road from {start} to {goal} on the {model.variant} junction")
