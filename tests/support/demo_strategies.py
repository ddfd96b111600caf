"""hypothesis strategies that build valid trajectories of every state/action kind."""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from symlearn.data import Demonstrations, Trajectory

PROPS = st.sampled_from(["a", "b", "key", "door", "goal", "hole_1"])
# NUL is refused by the data model (numpy strings cannot keep it), so never generate it.
def text(**kwargs):
    # no lone surrogates ("\ud800" is half a character, not text): the JSON readers refuse them
    return st.text(alphabet=st.characters(exclude_characters="\x00", exclude_categories=("Cs",)), **kwargs)


finite = st.floats(allow_nan=False, allow_infinity=False, width=64)
json_scalar = st.one_of(st.none(), st.booleans(), st.integers(-10**6, 10**6), finite, text(max_size=5))
info_dicts = st.dictionaries(text(min_size=1, max_size=6), json_scalar, max_size=3)


@st.composite
def state_columns(draw, kind: str, n: int, shape=None, dtype=None, keys=None):
    if kind == "discrete":
        return draw(st.lists(st.integers(-2**40, 2**40), min_size=n, max_size=n))
    if kind in ("vector", "image"):
        elements = finite if np.dtype(dtype).kind == "f" else None
        if np.dtype(dtype) == np.float32:
            elements = st.floats(allow_nan=False, allow_infinity=False, width=32)
        return draw(hnp.arrays(dtype, (n, *shape), elements=elements))
    if kind == "features":
        # one Python type per feature, as recorded environments produce
        types = {k: draw(st.sampled_from(["int", "float", "bool", "str"])) for k in keys}
        pick = {"int": st.integers(-100, 100), "float": finite, "bool": st.booleans(),
                "str": text(min_size=1, max_size=4)}
        return [{k: draw(pick[types[k]]) for k in keys} for _ in range(n)]
    return draw(st.lists(text(min_size=1, max_size=8), min_size=n, max_size=n))


@st.composite
def demonstrations(draw, kinds=("discrete", "vector", "image", "features", "symbol")):
    state_kind = draw(st.sampled_from(kinds))
    shape = dtype = keys = None
    if state_kind == "vector":
        shape = draw(st.sampled_from([(), (1,), (3,)]))
        dtype = draw(st.sampled_from([np.float64, np.float32, np.int64]))
    elif state_kind == "image":
        shape = draw(st.sampled_from([(2, 3), (2, 2, 3)]))
        dtype = draw(st.sampled_from([np.uint8, np.float32]))
    elif state_kind == "features":
        keys = draw(st.lists(text(min_size=1, max_size=5), min_size=1, max_size=3, unique=True))
    action_kind = draw(st.sampled_from([None, "discrete", "symbol", "vector"]))
    with_rewards = draw(st.booleans())
    with_labels = draw(st.booleans())
    trajectories = []
    for _ in range(draw(st.integers(1, 4))):
        n = draw(st.integers(1, 6))
        states = draw(state_columns(state_kind, n, shape, dtype, keys))
        actions = None
        if action_kind is not None:
            n_actions = draw(st.sampled_from([n, n - 1]))
            if action_kind == "vector":
                actions = draw(hnp.arrays(np.float64, (n_actions, 2), elements=finite))
            else:
                actions = draw(state_columns(action_kind, n_actions))
        n_rewards = n if actions is None else len(actions)
        rewards = draw(st.lists(finite, min_size=n_rewards, max_size=n_rewards)) if with_rewards else None
        labels = draw(st.lists(st.frozensets(PROPS, max_size=3), min_size=n, max_size=n)) if with_labels else None
        trajectories.append(Trajectory(states, actions, rewards, labels, draw(info_dicts)))
    return Demonstrations(trajectories, metadata=draw(info_dicts))
