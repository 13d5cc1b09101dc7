# Thin targets over scripts/. `make demo` and `make test` are the README's two commands.
.PHONY: setup demo test lint clean

setup:
	bash scripts/setup

demo:
	bash scripts/demo

test:
	bash scripts/test

lint: setup
	bash scripts/lint

clean:
	rm -rf build devel .ros
