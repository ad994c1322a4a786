# One profile (dev, optimised in Cargo.toml) serves tests and the report, so each builds once.
CARGO ?= cargo

.PHONY: all test report bench lint fmt doc

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

# API documentation with the thesis's equations rendered by KaTeX (as on docs.rs).
doc:
	RUSTDOCFLAGS="--html-in-header katex-header.html" $(CARGO) doc --no-deps
