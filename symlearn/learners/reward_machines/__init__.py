"""Reward machines from image demonstrations (thesis, chapter 7): features, prototypes, labeling,
Algorithm 7.1 and the reports that show what each machine state means."""

from symlearn.learners.reward_machines.labeling import PrototypeLabeling
from symlearn.learners.reward_machines.rm_inference import RewardMachineInference

__all__ = ["PrototypeLabeling", "RewardMachineInference"]
