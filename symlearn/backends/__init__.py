"""Compile a learned artefact into something an RL agent uses: shields, costs, reward machines.

* :class:`~symlearn.backends.shield.Shield` -- a gymnasium wrapper that exposes
  ``info["action_mask"]`` (and ``action_masks()`` for masked policies such as sb3-contrib's
  ``MaskablePPO``) and refuses or replaces forbidden actions.
* :class:`~symlearn.backends.cost.CostWrapper` -- a gymnasium wrapper adding ``info["cost"]``.
* :mod:`~symlearn.backends.masks` -- a constraint set over a domain model's ids as the mask of an
  environment: :func:`~symlearn.backends.masks.closed_mask` (closed with
  :func:`~symlearn.rl.tabular.restrict`) and :func:`~symlearn.backends.masks.env_mask` (cut to the
  environment's observation ids).
* :class:`~symlearn.backends.reward_machine.RewardMachineWrapper` -- a reward machine on any
  gymnasium environment plus a labeling: the machine state joins the observation, the machine
  pays the reward (optionally potential-shaped), acceptance ends the episode, and counterfactual
  (CRM) experiences are offered for off-policy learners;
  :func:`~symlearn.backends.reward_machine.task_machine` compiles an LTLf task into a machine.
* :mod:`~symlearn.backends.dnf_cost`, :mod:`~symlearn.backends.neural_cost` -- a learned DNF or
  neural cost in the forms the trainers take: a whole PPO rollout's cost (or reward ``r - C``),
  and one step's cost for stable-baselines3.
* :mod:`~symlearn.backends.sb3` -- stable-baselines3 glue (optional extra ``sb3``): a callback
  that puts counterfactual experiences into a replay buffer.

Shields and cost wrappers accept a forbidden ``(S, A)`` mask (a constraint set), any
``allowed(state, action)`` callable (an ASP hypothesis plugs in here through its ``allowed``
method), and the cost wrapper also ``lambda . phi`` from MCE-ICRL.
"""

from symlearn.backends.cost import CostWrapper
from symlearn.backends.masks import closed_mask, env_mask
from symlearn.backends.reward_machine import Experience, RewardMachineWrapper, task_machine
from symlearn.backends.shield import Shield

__all__ = ["CostWrapper", "Experience", "RewardMachineWrapper", "Shield", "closed_mask", "env_mask", "task_machine"]
