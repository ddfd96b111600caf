"""Record the guide's demonstrations: python record_demos.py [--episodes N]

demos.npz        careful robot runs in GuideRobot-v0 (DNF constraints, neural costs)
tour.npz         tours of the two stations, positions (sub-goal automata)
tour_video.npz   tours through the camera (24 x 24 pictures), charger first (reward machines)
"""

import argparse

import gymnasium as gym

import guide_robot  # noqa: F401 -- registers GuideRobot-v0 and GuideTour-v0
from symlearn.data import record

parser = argparse.ArgumentParser()
parser.add_argument("--episodes", type=int, default=20)
n = parser.parse_args().episodes

env = gym.make("GuideRobot-v0")
record(env, guide_robot.careful_expert(), n, seed=0).save("demos.npz")

for name, camera in (("tour.npz", False), ("tour_video.npz", True)):
    env = gym.make("GuideTour-v0", camera=camera)
    # the camera tours keep one order (charger, then dock): a reward machine is a sequence task
    expert = guide_robot.tour_expert(env, prefer_charger=1.0 if camera else 0.8)
    record(env, expert, n, seed=0).save(name)
print(f"wrote demos.npz, tour.npz, tour_video.npz ({n} episodes each)")
