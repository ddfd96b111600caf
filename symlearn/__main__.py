from symlearn.cli.main import run

run()
