"""A progress bar that records what it is given (tests of the learners' bars)."""

from symlearn.progress import ProgressBar


def recording_bar(monkeypatch, module) -> list:
    """Replace ``module.ProgressBar`` by one that appends every ``update``'s numbers to the list returned."""
    shown = []

    class Recording(ProgressBar):
        def update(self, n=1, **numbers):
            shown.append(numbers)
            super().update(n, **numbers)

    monkeypatch.setattr(module, "ProgressBar", Recording)
    return shown
