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
