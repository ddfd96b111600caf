"""Every package folder must be a regular package, or setup.py's find_packages leaves it out of wheels."""

from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "symlearn"


def test_every_folder_with_modules_has_an_init():
    missing = [str(d.relative_to(PACKAGE.parent)) for d in PACKAGE.rglob("*")
               if d.is_dir() and d.name != "__pycache__" and any(d.glob("*.py")) and not (d / "__init__.py").exists()]
    assert not missing, f"add __init__.py to: {missing}"
