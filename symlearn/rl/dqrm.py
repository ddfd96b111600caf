"""Deep Q-learning on a reward machine (DQRM, thesis section 7.5) and its DQN baselines.

The action is a pick pixel and a place pixel on a top-down image. Two small *fully convolutional*
networks map the image to a Q-value per pixel: ``pick`` reads the
observation, ``place`` the observation stacked with the top-down *prototype* of an outgoing
transition of the current machine state (where the blocks should be next); the place map is the
best over the outgoing transitions. ``Q(s, a)`` is learned on both maps at the executed pixels only
(Huber loss, eq. 7.1) against one target ``y = r + gamma * V(s')`` with
``V(s') = (max pick(s') + max place(s')) / 2`` (each half assumes the other acts greedily).

Two departures from the thesis' text, both measured (docs/BENCHMARKS.md, "DQRM and DQN"):

* ``V(s')`` comes from *target networks* copied from the online ones every ``target_sync``
  updates, with *double Q-learning* (the online maps choose the transition and the pixels, the
  target maps value them): bootstrapping on the online maps' own max over ~2300 pixels drove Q
  above the largest return the machine pays (1.12 where 1.0 is the most) on the seed that failed;
* no coordinate channels by default (``coordinates=False``): the thesis' networks have none, and
  with them an *empty* table pixel can take a value of its own, so the greedy pick landed on a
  spurious maximum in an empty corner; without them the map is translation-equivariant and what
  it learns about one empty pixel holds for all of them.

``method``:

* ``"dqrm"``: one pair of networks and one replay buffer per machine state (the machine state
  picks the networks), reward = the machine's (shaped) reward, prototypes from ``prototypes``;
* ``"dqn-shaped"``: one pair for every machine state, the same machine reward, no machine state
  (the place network sees a blank prototype): the thesis' ablation of the machine state;
* ``"dqn-sparse"``: one pair, the environment's sparse reward.

Buffers hold interactions and the demonstrator's transitions (``demonstrations``: lists of actions
replayed in the environment; every batch is half demonstrations while there are any). Epsilon-
greedy from ``epsilon_start`` decaying exponentially to ``epsilon_end``; Adam; networks updated at
the end of every episode. Every ``eval_every`` episodes a greedy episode (epsilon 0) is recorded:
machine return, task success (the environment's sparse reward) and the final placement error.

The environment is anything with the :class:`~symlearn.envs.rendered_blocks.env.RenderedBlocksEnv`
interface (MultiDiscrete pick/place pixels, ``info["front"]`` for the labeling, ``info
["placement_error"]``); the machine anything with ``initial``, ``n_states``, ``step(u, label)``,
``is_terminal(u)`` and ``successors(u)``; the labeling a callable ``info -> propositions``.
``torch.set_num_threads(1)`` while training (measured faster on the 2-core machines).
"""

from __future__ import annotations

import copy
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import torch
from torch import nn

from symlearn.errors import DataError
from symlearn.progress import progress

METHODS = ("dqrm", "dqn-shaped", "dqn-sparse")


@dataclass(frozen=True)
class DQRMConfig:
    episodes: int = 200
    gamma: float = 0.9
    learning_rate: float = 1e-4
    batch_size: int = 16
    epsilon_start: float = 0.7
    epsilon_end: float = 0.1
    updates_per_episode: int = 4
    buffer_size: int = 2000
    channels: int = 16
    eval_every: int = 5
    torch_threads: int = 1
    target_sync: int = 16  # updates between copies of the online networks into the target ones; 0: no target networks
    coordinates: bool = False  # two coordinate channels (row, column) beside the colours (docs/BENCHMARKS.md: off)
    double_q: bool = True  # the online maps choose the next branch and pixels, the target maps value them


@dataclass(frozen=True)
class Evaluation:
    episode: int
    machine_return: float
    success: float
    placement_error: float
    steps: int

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)


@dataclass
class DQRMResult:
    method: str
    networks: nn.ModuleDict
    history: list[Evaluation] = field(default_factory=list)
    episode_returns: list[float] = field(default_factory=list)
    seconds: float = 0.0
    network: dict[str, Any] = field(default_factory=dict)  # what rebuilding the networks needs

    def save(self, path: str | os.PathLike[str], config: dict[str, Any]) -> Path:
        from symlearn.rl.model_files import save_torch_module

        return save_torch_module(path, self.networks, {"method": self.method, **self.network, **config},
                                 kind="symlearn-dqrm")


def pixel_network(in_channels: int, channels: int, coordinates: bool = False) -> nn.Sequential:
    """A fully convolutional map from an image (+ two coordinate channels) to one Q-value per pixel."""
    return nn.Sequential(
        nn.Conv2d(in_channels + 2 * coordinates, channels, 3, padding=1), nn.ReLU(),
        nn.Conv2d(channels, channels, 3, padding=2, dilation=2), nn.ReLU(),
        nn.Conv2d(channels, channels, 3, padding=4, dilation=4), nn.ReLU(),
        nn.Conv2d(channels, 1, 1))


def _tensor(images: np.ndarray) -> torch.Tensor:
    """uint8 (N, H, W, 3) -> float (N, 5, H, W) with coordinate channels."""
    x = torch.from_numpy(np.ascontiguousarray(images, dtype=np.float32) / 255.0).permute(0, 3, 1, 2)
    n, _, h, w = x.shape
    rows = torch.linspace(-1, 1, h).view(1, 1, h, 1).expand(n, 1, h, w)
    cols = torch.linspace(-1, 1, w).view(1, 1, 1, w).expand(n, 1, h, w)
    return torch.cat([x, rows, cols], dim=1)


class _Buffer:
    def __init__(self, size: int):
        self.size, self.items = size, []

    def add(self, item) -> None:
        self.items.append(item)
        if len(self.items) > self.size:
            self.items.pop(0)

    def sample(self, n: int, rng: np.random.Generator) -> list:
        return [self.items[i] for i in rng.integers(0, len(self.items), n)] if self.items else []


def train_dqrm(env_fn: Callable[[], Any], machine: Any, labeling: Callable[[dict], frozenset],
               prototypes: np.ndarray, *, method: str = "dqrm", demonstrations: Sequence[Sequence] = (),
               config: DQRMConfig = DQRMConfig(), seed: int = 0, callback: Callable[[Evaluation], None] | None = None
               ) -> DQRMResult:
    """Train (see the module docstring). ``labeling(info) -> propositions`` reads a step's ``info``
    (``info["front"]`` for an inferred labeling, ``info["truth"]`` for the ground truth);
    ``prototypes``: one top-down image per machine state ``(n, H, W, 3)``."""
    if method not in METHODS:
        raise DataError(f"unknown method {method!r}", hint="use " + ", ".join(METHODS))
    prototypes = np.asarray(prototypes)
    if prototypes.ndim != 4 or len(prototypes) != machine.n_states:
        raise DataError(f"{len(prototypes)} prototypes of shape {prototypes.shape[1:]} for a machine of "
                        f"{machine.n_states} states; give one top-down image per state")
    threads = torch.get_num_threads()
    torch.set_num_threads(config.torch_threads)
    try:
        return _train(env_fn, machine, labeling, prototypes, method, demonstrations, config, seed, callback)
    finally:
        torch.set_num_threads(threads)


def _bootstrap_values(online: tuple[torch.Tensor, torch.Tensor], target: tuple[torch.Tensor, torch.Tensor],
                      double_q: bool) -> torch.Tensor:
    """``V(s')`` per row from pick and place maps ``(B, T, H, W)``: the mean of the best pick and the
    best place of the best transition. With ``double_q`` the online maps choose the transition and the
    pixels and the target maps value that choice (van Hasselt et al.'s double Q-learning): a max over
    2304 noisy pixels is biased upward, and feeding it back as a target let Q exceed the largest
    return the machine pays (docs/BENCHMARKS.md, DQRM). Without it, the target maps' own max."""
    t_pick, t_place = target
    if not double_q:
        return (0.5 * (t_pick.flatten(2).max(2).values + t_place.flatten(2).max(2).values)).max(1).values
    o_pick, o_place = online
    rows = torch.arange(len(o_pick))
    best_pick, best_place = o_pick.flatten(2).max(2), o_place.flatten(2).max(2)
    branch = (0.5 * (best_pick.values + best_place.values)).argmax(1)
    pick = t_pick.flatten(2)[rows, branch, best_pick.indices[rows, branch]]
    place = t_place.flatten(2)[rows, branch, best_place.indices[rows, branch]]
    return 0.5 * (pick + place)


def _train(env_fn, machine, labeling, prototypes, method, demonstrations, config, seed, callback) -> DQRMResult:
    started = time.perf_counter()
    torch.manual_seed(seed)
    rng = np.random.default_rng(seed)
    env = env_fn()
    per_state = method == "dqrm"
    n_nets = machine.n_states if per_state else 1
    networks = nn.ModuleDict({f"pick{k}": pixel_network(6, config.channels, config.coordinates) for k in range(n_nets)})
    networks.update({f"place{k}": pixel_network(6, config.channels, config.coordinates) for k in range(n_nets)})
    optimiser = torch.optim.Adam(networks.parameters(), lr=config.learning_rate)
    # DQN's target networks (Mnih et al. 2015, the thesis' [31]): bootstrap from a copy refreshed
    # every ``target_sync`` updates, so a step does not chase its own moving estimate
    target_networks = copy.deepcopy(networks).requires_grad_(False) if config.target_sync > 0 else networks
    updates_done = 0
    blank = np.zeros_like(prototypes[0])
    targets = {u: sorted({e[1] for e in machine.successors(u) if e[1] != u}) or [u] for u in range(machine.n_states)}
    buffers = {k: _Buffer(config.buffer_size) for k in range(n_nets)}
    demo_buffers = {k: _Buffer(config.buffer_size) for k in range(n_nets)}

    def net_of(u: int) -> int:
        return u if per_state else 0

    def conditions(u: int) -> np.ndarray:
        return prototypes[targets[u]] if per_state else blank[None]

    def batch_maps(images: np.ndarray, u: int, nets: nn.ModuleDict = networks) -> tuple[torch.Tensor, torch.Tensor]:
        """Pick and place Q-maps ``(B, T, H, W)`` of observations in machine state ``u``, one per
        outgoing transition (its prototype stacked on the observation)."""
        k = net_of(u)
        x = _tensor(images)
        b, _, h, w = x.shape
        cond = _tensor(conditions(u))
        if not config.coordinates:
            x, cond = x[:, :3], cond[:, :3]
        t, c = len(cond), cond.shape[1]
        stacked = torch.cat([x[:, None, :3].expand(b, t, 3, h, w), cond[None].expand(b, t, c, h, w)], dim=2)
        stacked = stacked.reshape(b * t, 3 + c, h, w)
        pick = nets[f"pick{k}"](stacked)[:, 0].reshape(b, t, h, w)
        place = nets[f"place{k}"](stacked)[:, 0].reshape(b, t, h, w)
        return pick, place

    def values(pick: torch.Tensor, place: torch.Tensor) -> torch.Tensor:
        """``(B, T)``: value of each transition = mean of the best pick and the best place."""
        return 0.5 * (pick.flatten(2).max(2).values + place.flatten(2).max(2).values)

    def step_machine(u: int, info: dict, env_reward: float, terminated: bool):
        u2, r = machine.step(u, labeling(info))
        if method == "dqn-sparse":  # the machine is only tracked (for the records), never rewarded
            return u2, env_reward, terminated
        return u2, r, terminated or machine.is_terminal(u2)

    def greedy(obs: np.ndarray, u: int) -> tuple[np.ndarray, int]:
        """The best transition to aim for, then the best pick and place for it (one branch: two
        independent argmaxes could pick one block and place it where another one belongs)."""
        with torch.no_grad():
            pick, place = batch_maps(obs[None], u)
            branch = int(values(pick, place)[0].argmax())
        p, q = pick[0, branch], place[0, branch]
        return np.array([*np.unravel_index(int(p.argmax()), p.shape), *np.unravel_index(int(q.argmax()), q.shape)]), branch

    def branch_of(u: int, u2: int, chosen: int) -> int:
        """The transition a step trains: the one it took, else the one it aimed for."""
        if not per_state:  # no machine state: one blank prototype, one branch
            return 0
        return targets[u].index(u2) if u2 in targets[u] else chosen

    # demonstrations into the buffers
    for actions in demonstrations:
        obs, info = env.reset(seed=int(rng.integers(2 ** 31)))
        u = machine.initial
        for action in actions:
            next_obs, env_r, terminated, truncated, info = env.step(action)
            u2, reward, done = step_machine(u, info, env_r, terminated)
            demo_buffers[net_of(u)].add((obs, np.asarray(action), reward, next_obs, u, u2, done, branch_of(u, u2, 0)))
            obs, u = next_obs, u2
            if done or truncated:
                break

    def update() -> None:
        nonlocal updates_done
        if config.target_sync > 0 and updates_done % config.target_sync == 0:
            target_networks.load_state_dict(networks.state_dict())
        updates_done += 1
        for k in range(n_nets):
            half = config.batch_size // 2 if demo_buffers[k].items else 0
            batch = demo_buffers[k].sample(half, rng) + buffers[k].sample(config.batch_size - half, rng)
            if not batch:
                continue
            obs, actions, rewards, next_obs, us, next_us, dones, branches = (list(column) for column in zip(*batch))
            actions, next_obs = np.asarray(actions), np.asarray(next_obs)
            bootstrap = np.zeros(len(batch))
            with torch.no_grad():  # V(s') = the best transition's value, per next machine state
                for u2 in set(u for u, done in zip(next_us, dones) if not done):
                    rows = [i for i, (v, done) in enumerate(zip(next_us, dones)) if v == u2 and not done]
                    target = batch_maps(next_obs[rows], u2, target_networks)
                    online = batch_maps(next_obs[rows], u2) if config.double_q else target
                    bootstrap[rows] = _bootstrap_values(online, target, config.double_q).numpy()
            y = torch.tensor(np.asarray(rewards) + config.gamma * bootstrap, dtype=torch.float32)
            pick, place = batch_maps(np.asarray(obs), us[0])  # one machine state per buffer (or no machine state)
            index, branch = torch.arange(len(batch)), torch.as_tensor(branches)
            loss = nn.functional.huber_loss(pick[index, branch, actions[:, 0], actions[:, 1]], y) + \
                nn.functional.huber_loss(place[index, branch, actions[:, 2], actions[:, 3]], y)
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()

    def evaluate(episode: int) -> Evaluation:
        obs, info = env.reset(seed=10_000 + episode)
        u, total, success, steps = machine.initial, 0.0, 0.0, 0
        while True:
            obs, env_r, terminated, truncated, info = env.step(greedy(obs, u)[0])
            u, reward, done = step_machine(u, info, env_r, terminated)
            total += reward
            success = max(success, env_r)
            steps += 1
            if done or truncated:
                break
        return Evaluation(episode, total, success, float(info["placement_error"]), steps)

    result = DQRMResult(method, networks, network={"channels": config.channels, "coordinates": config.coordinates})
    decay = (config.epsilon_end / config.epsilon_start) ** (1 / max(config.episodes - 1, 1))
    for episode in progress(range(config.episodes), total=config.episodes, desc=method):
        epsilon = config.epsilon_start * decay ** episode
        obs, info = env.reset(seed=int(rng.integers(2 ** 31)))
        u, total = machine.initial, 0.0
        while True:
            if rng.random() < epsilon:
                # drawn from the run's own generator: the action space's is not seeded by reset(seed)
                action = rng.integers(0, env.action_space.nvec)
                chosen = int(rng.integers(len(targets[u]) if per_state else 1))
            else:
                action, chosen = greedy(obs, u)
            next_obs, env_r, terminated, truncated, info = env.step(action)
            u2, reward, done = step_machine(u, info, env_r, terminated)
            buffers[net_of(u)].add((obs, np.asarray(action), reward, next_obs, u, u2, done, branch_of(u, u2, chosen)))
            total += reward
            obs, u = next_obs, u2
            if done or truncated:
                break
        result.episode_returns.append(total)
        for _ in range(config.updates_per_episode):
            update()
        if (episode + 1) % config.eval_every == 0:
            record = evaluate(episode + 1)
            result.history.append(record)
            if callback is not None:
                callback(record)
    result.seconds = time.perf_counter() - started
    return result


__all__ = ["DQRMConfig", "DQRMResult", "Evaluation", "METHODS", "pixel_network", "train_dqrm"]
