"""From learned constraints to things an RL agent can use: shields and cost signals.

* :class:`~symlearn.backends.shield.Shield` -- a gymnasium wrapper that exposes
  ``info["action_mask"]`` and refuses or replaces forbidden actions.
* :class:`~symlearn.backends.cost.CostWrapper` -- a gymnasium wrapper adding ``info["cost"]``.

Both accept a forbidden ``(S, A)`` mask (a constraint set), any ``allowed(state, action)``
callable (an ASP hypothesis plugs in here through its ``allowed`` method), and the cost
wrapper also ``lambda . phi`` from MCE-ICRL.
"""

from symlearn.backends.cost import CostWrapper
from symlearn.backends.shield import Shield

__all__ = ["CostWrapper", "Shield"]
