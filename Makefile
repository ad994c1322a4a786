# One profile (dev, optimised in Cargo.toml) serves tests and the report, so each builds once.
CARGO ?= cargo

.PHONY: all test report bench lint fmt

all: test report

test:
	$(CARGO) test --all-targets

report:
	$(CARGO) run --bin report

bench:
	$(CARGO) bench --bench steps

lint:
	$(CARGO) fmt --check
	$(CARGO) clippy --all-targets -- -D warnings

fmt:
	$(CARGO) fmt
