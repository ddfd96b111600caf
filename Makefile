# The two entry points of the README. Both are idempotent: scripts/bootstrap.sh only
# installs what is missing or what pyproject.toml changed since the last install.
.PHONY: demo test

demo:
	@bash scripts/bootstrap.sh
	@.venv/bin/symlearn demo

test:
	@bash scripts/bootstrap.sh --with-tests
	@.venv/bin/python -m pytest -n auto --dist loadfile
