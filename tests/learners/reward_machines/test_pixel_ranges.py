"""Frames outside the pixel ranges the features assume are refused, not scaled wrongly."""

import json

import numpy as np
import pytest

from symlearn.errors import DataError
from symlearn.learners.reward_machines.features import as_frames
from tests.support.cli_runner import run


def test_integer_frames_beyond_8_bits_are_refused():
    with pytest.raises(DataError, match=r"must lie in 0\.\.255 .*\[40000, 40000\]"):
        as_frames(np.full((2, 8, 8, 3), 40000, dtype=np.uint16))
    assert as_frames(np.full((2, 8, 8, 3), 255, np.int32)).max() == 1.0


def test_learn_rm_reports_the_range_of_all_frames(tmp_path, capsys):
    # frames as floats 0..255: the message gives the range of them all, not of the first one
    states = np.full((6, 8, 8, 3), 200.0, dtype=np.float32)
    states[0], states[4] = 100.0, 0.0
    path = tmp_path / "video.npz"
    np.savez(path, __meta__=json.dumps({"symlearn": "demonstrations", "format_version": 1, "state_kind": "image"}),
             states=states, lengths=np.array([3, 3]))
    code, _, err = run(capsys, "learn", "rm", "--demos", path)
    assert code == 2 and "got [0, 200]" in err, err


def test_a_table_of_features_is_told_apart_from_pictures():
    # highway-env's kinematics, a (5, 5) float table per step with negative values, was told to
    # "scale to 0..1" as if it were a camera frame
    import numpy as np
    import pytest

    from symlearn.errors import DataError
    from symlearn.learners.reward_machines.features import check_pixel_values

    with pytest.raises(DataError) as table:
        check_pixel_values(np.linspace(-2, 2, 250).reshape(10, 5, 5))
    assert "tables of features" in table.value.hint and "learn dnf" in table.value.hint
    with pytest.raises(DataError) as picture:
        check_pixel_values(np.linspace(0, 2, 10 * 32 * 32).reshape(10, 32, 32))
    assert "tables of features" not in picture.value.hint
    check_pixel_values(np.linspace(0, 1, 250).reshape(10, 5, 5))  # a tiny picture in range is fine
