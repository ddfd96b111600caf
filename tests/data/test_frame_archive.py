"""Frame archives: NaN kept, infinities and inconsistent lengths refused with the file named."""

import numpy as np
import pytest

from symlearn.data.frame_archive import is_frame_archive, load_frames, save_frames
from symlearn.errors import DataError


def test_round_trip_keeps_nan_and_names(tmp_path):
    runs = [np.array([[0.0, np.nan], [1.0, 2.0]]), np.arange(6.0).reshape(3, 2)]
    path = save_frames(tmp_path / "f.npz", runs, ["a", "b"])
    assert is_frame_archive(path)
    loaded, names = load_frames(path)
    assert names == ("a", "b") and all(np.array_equal(x, y, equal_nan=True) for x, y in zip(loaded, runs))


@pytest.mark.parametrize("members, message", [
    ({"states": np.zeros((3, 2))}, "needs a member 'lengths'"),
    ({"states": np.zeros((3, 2)), "lengths": np.array([1, 1])}, "sum to the 3 rows"),
    ({"states": np.zeros((3, 2)), "lengths": np.array([3, 0])}, "positive"),
    ({"states": np.zeros(3), "lengths": np.array([3])}, "(frames, features)"),
    ({"states": np.zeros((2, 2)), "lengths": np.array([2]), "feature_names": np.array(["a"])}, "2 strings"),
])
def test_bad_archives_name_the_file(tmp_path, members, message):
    path = tmp_path / "bad.npz"
    np.savez(path, **members)
    with pytest.raises(DataError) as info:
        load_frames(path)
    assert message in str(info.value) and info.value.file == str(path)


def test_object_arrays_are_refused_before_loading(tmp_path):
    path = tmp_path / "obj.npz"
    np.savez(path, states=np.array([[None]], dtype=object), lengths=np.array([1]))
    with pytest.raises(DataError, match="dtype"):
        load_frames(path)


def test_repeated_or_empty_feature_names_are_refused(tmp_path):
    import numpy as _np
    import pytest as _pytest

    from symlearn.data.frame_archive import load_frames
    from symlearn.errors import DataError as _DataError

    for names, message in ((["a", "a"], "names 'a' twice"), (["a", " "], "has an empty name")):
        path = tmp_path / "f.npz"
        _np.savez(path, states=_np.zeros((4, 2)), lengths=_np.array([2, 2]), feature_names=_np.array(names))
        with _pytest.raises(_DataError, match=message):
            load_frames(path)
