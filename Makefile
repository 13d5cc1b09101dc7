# Thin targets over scripts/. `make demo` and `make test` are the README's two commands.
.PHONY: setup demo test test-long lint clean train

setup:
	bash scripts/setup

demo:
	bash scripts/demo

test:
	bash scripts/test

# the long closed-loop checks `make test` leaves out (README.md, "The long tests")
test-long:
	bash scripts/test_long

# `make train ARGS=--install` also copies the models over models/semantic_nav/
train:
	bash -c 'source scripts/env.sh && python3 scripts/train_recipe $(ARGS)'

lint: setup
	bash scripts/lint

clean:
	rm -rf build devel .ros
