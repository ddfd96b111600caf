"""The source of a user module with a Dict-observing gymnasium environment (written to a temporary
folder and imported as ``lift_lab:DictLift-v0`` by CLI tests)."""

DICT_ROBOT = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class Lift(gym.Env):
    """A lift between 4 floors with a door: Dict(floor=Discrete(4), door=Discrete(2))."""

    def __init__(self):
        self.observation_space = spaces.Dict({"floor": spaces.Discrete(4), "door": spaces.Discrete(2)})
        self.action_space = spaces.Discrete(3)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.floor, self.door = 0, 0
        return {"floor": self.floor, "door": self.door}, {}

    def step(self, action):
        if action == 0:
            self.door = 1 - self.door
        else:
            self.floor = int(np.clip(self.floor + (1 if action == 1 else -1), 0, 3))
        done = self.floor == 3 and self.door == 1
        return {"floor": self.floor, "door": self.door}, float(done), done, False, {}


gym.register(id="DictLift-v0", entry_point=lambda: gym.wrappers.TimeLimit(Lift(), 12))
'''


def lift_demonstrations(tmp_path, monkeypatch, episodes: int) -> str:
    """Write the module into ``tmp_path``, import it (registering ``DictLift-v0``), change into
    ``tmp_path`` and record ``episodes`` expert episodes (up, up, up, open) to ``lift.jsonl``."""
    import gymnasium

    from symlearn.data import record

    (tmp_path / "lift_lab.py").write_text(DICT_ROBOT)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import lift_lab  # noqa: F401 -- registers DictLift-v0

    plan = iter([1, 1, 1, 0] * episodes)
    record(gymnasium.make("DictLift-v0"), lambda obs: next(plan), episodes, seed=0).save(tmp_path / "lift.jsonl")
    return "lift.jsonl"


VECTOR_ROVER = '''
import gymnasium as gym
import numpy as np
from gymnasium import spaces


class Rover(gym.Env):
    """A 2-D point observed as Dict(pos=Box(2), vel=Box(2), moving=Discrete(2)); info["cost"]
    right of x = 0.6. The policy's view one-hots ``moving``; recorded states keep it one column."""

    def __init__(self):
        self.observation_space = spaces.Dict({"pos": spaces.Box(-1, 1, (2,), np.float32),
                                              "vel": spaces.Box(-1, 1, (2,), np.float32),
                                              "moving": spaces.Discrete(2)})
        self.action_space = spaces.Box(-1, 1, (2,), np.float32)

    def _obs(self):
        return {"pos": self.p.astype(np.float32), "vel": self.v.astype(np.float32),
                "moving": int(np.abs(self.v).sum() > 0.01)}

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.p, self.v = self.np_random.uniform(-0.9, -0.5, 2), np.zeros(2)
        return self._obs(), {}

    def step(self, action):
        self.v = np.clip(0.5 * self.v + 0.05 * np.clip(action, -1, 1), -1, 1)
        self.p = np.clip(self.p + self.v, -1, 1)
        return self._obs(), -float(abs(self.p[1] - 0.5)), False, False, {"cost": float(self.p[0] > 0.6)}


gym.register(id="VectorRover-v0", entry_point=lambda: gym.wrappers.TimeLimit(Rover(), 40))
'''


def rover_demonstrations(tmp_path, monkeypatch, episodes: int) -> str:
    """Write the vector-Dict module into ``tmp_path``, import it (``vector_rover:VectorRover-v0``),
    change into ``tmp_path`` and record ``episodes`` episodes of an expert heading for y = 0.5 while
    keeping x below 0.2, to ``rover.npz``."""
    import gymnasium
    import numpy as np

    from symlearn.data import record

    (tmp_path / "vector_rover.py").write_text(VECTOR_ROVER)
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))
    import vector_rover  # noqa: F401 -- registers VectorRover-v0

    def expert(obs):
        target = np.array([min(obs["pos"][0], 0.2), 0.5])
        return np.clip(5 * (target - obs["pos"]) - 2 * obs["vel"], -1, 1).astype(np.float32)

    record(gymnasium.make("VectorRover-v0"), expert, episodes, seed=0).save(tmp_path / "rover.npz")
    return "rover.npz"
