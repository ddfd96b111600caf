"""The guide's labeling function: which propositions hold at one step of GuideTour-v0.

`--labeling labels.py:label` and `record(..., labeler=label)` call it with the observation and the
`info` dict of that step; it reads the position from `info["features"]`, so the camera variant
(whose observation is a picture) is labelled the same way.
"""

import numpy as np

from guide_robot import CHARGER, DOCK, STATION_RADIUS


def label(observation, info):
    position = np.asarray(info["features"], dtype=float)
    return [name for name, where in (("charger", CHARGER), ("dock", DOCK))
            if np.linalg.norm(position - where) < STATION_RADIUS]
