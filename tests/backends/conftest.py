import pytest


@pytest.fixture
def one_torch_thread():
    """Small networks train several times faster on one thread than on two."""
    torch = pytest.importorskip("torch")
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(threads)


@pytest.fixture(autouse=True)
def sb3_logs_in_a_temporary_folder(tmp_path_factory, monkeypatch):
    """These tests call stable-baselines3's ``learn`` directly, whose default logger makes an empty
    ``SB3-<date>`` folder in the system's temporary directory on every call (the CLI gives it a
    logger without one): here it goes to pytest's own temporary folders, which pytest prunes."""
    monkeypatch.setenv("SB3_LOGDIR", str(tmp_path_factory.mktemp("sb3_logs")))
