"""A labeling-function file for MiniGrid DoorKey, loaded as ``minigrid_doorkey_labels.py:label``.

MiniGrid's observation is the agent's partial view, which hides the cell the agent stands on,
so the function takes the third, optional argument: the unwrapped environment.
"""

from minigrid.core.world_object import Door, Goal, Key

PROPOSITIONS = ["has_key", "door_open", "at_goal"]


def label(observation, info, env):
    found = set()
    if isinstance(env.carrying, Key):
        found.add("has_key")
    if any(isinstance(cell, Door) and cell.is_open for cell in env.grid.grid):
        found.add("door_open")
    if isinstance(env.grid.get(*env.agent_pos), Goal):
        found.add("at_goal")
    return found
