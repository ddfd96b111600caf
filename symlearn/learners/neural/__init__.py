"""Neural learners: maximum causal entropy inverse constrained RL with a neural feature network
(thesis chapter 2) and the ME-ICRL, VME-ICRL and GACL baselines, the learned cost and the ICRL metrics
(episodes as arrays and the PPO-Lagrangian expert live in :mod:`symlearn.rl`)."""

from symlearn.learners.neural.gacl import GACLIteration, NeuralGACL
from symlearn.learners.neural.mce_icrl import ICRLIteration, NeuralMCEICRL
from symlearn.learners.neural.me_icrl import MEIteration, NeuralMEICRL
from symlearn.learners.neural.neural_cost import NeuralCost
from symlearn.learners.neural.vme_icrl import NeuralVMEICRL, VMEIteration

__all__ = ["GACLIteration", "ICRLIteration", "MEIteration", "NeuralCost", "NeuralGACL", "NeuralMCEICRL",
           "NeuralMEICRL", "NeuralVMEICRL", "VMEIteration"]
