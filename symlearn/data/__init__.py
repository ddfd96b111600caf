"""Data layer: trajectories, demonstrations, safe file formats and recording."""

from symlearn.data.demonstrations import Demonstrations
from symlearn.data.files import load, save
from symlearn.data.trajectory import Trajectory

__all__ = ["Demonstrations", "Trajectory", "load", "save", "record"]


def __getattr__(name: str):
    # recording imports gymnasium helpers lazily: the data layer stays light for logic-only users.
    if name == "record":
        from symlearn.data.recording import record

        return record
    raise AttributeError(name)
