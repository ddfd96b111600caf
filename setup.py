# Only package discovery lives here (pyproject.toml has everything else): setuptools' TOML
# configuration cannot combine found packages with folders mapped from outside symlearn/.
from setuptools import find_packages, setup

setup(
    packages=find_packages(include=["symlearn", "symlearn.*"]) + ["symlearn.grammars", "symlearn.background_kb"],
    package_dir={"symlearn.grammars": "grammars", "symlearn.background_kb": "background_kb"},
)
