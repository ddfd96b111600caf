"""Data layer: trajectories, demonstrations, safe file formats (symlearn's, D4RL, Minari), the
imitation library's trajectories, and recording."""

from symlearn.data.demonstrations import Demonstrations
from symlearn.data.files import load, save
from symlearn.data.trajectory import Trajectory

__all__ = ["Demonstrations", "Trajectory", "load", "save", "record", "from_imitation", "to_imitation"]


def __getattr__(name: str):
    # recording imports gymnasium helpers lazily: the data layer stays light for logic-only users.
    if name == "record":
        from symlearn.data.recording import record

        return record
    if name in ("from_imitation", "to_imitation"):
        from symlearn.data import imitation_bridge

        return getattr(imitation_bridge, name)
    raise AttributeError(name)
