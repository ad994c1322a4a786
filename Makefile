# One profile (dev, optimised in Cargo.toml) and one feature set (resolver 1 in Cargo.toml) serve
# tests and the report, so after `make test` the report compiles nothing. Benches are built by
# `make bench` only (clippy in `make lint` still checks them).
CARGO ?= cargo

.PHONY: all test report report-long bench lint fmt doc doc-offline timing

all: test report

# tests/thesis (the result set the report computes, on both cores) runs beside the other test
# binaries, which cargo would otherwise run after it one at a time; its output follows theirs.
# Either failing fails the target.
OTHER_TESTS := $(patsubst %.rs,--test %,$(notdir $(wildcard tests/*.rs presentation/tests/*.rs)))

test:
	$(CARGO) test --lib --bins --tests --no-run
	@mkdir -p target; \
	$(CARGO) test --test thesis > target/thesis-tests.log 2>&1 & thesis=$$!; \
	$(CARGO) test --lib --bins $(OTHER_TESTS); others=$$?; \
	wait $$thesis; status=$$?; \
	echo "== tests/thesis (run beside the others)"; cat target/thesis-tests.log; \
	test $$others -eq 0 && test $$status -eq 0

report:
	$(CARGO) run --bin report

# The benchmark's long runs (deterministic, committed): report/long/, which `make report` reads.
# Run it before `make report` when the benchmark changes; .ci/run fails when it is stale.
report-long:
	$(CARGO) run --bin report_long

bench:
	$(CARGO) bench --bench steps

# The sheet's scaling study (n = 10 to 320 at k = 1e6): report/timing/ (TIMING.md, CSVs, figure),
# outside the byte-identical report. A few minutes on 2 cores; progress on stderr.
timing:
	$(CARGO) run --bin timing

lint:
	$(CARGO) fmt --check
	$(CARGO) clippy --all-targets -- -D warnings

fmt:
	$(CARGO) fmt

# API documentation with the thesis's equations rendered by KaTeX from its CDN (as on docs.rs).
doc:
	RUSTDOCFLAGS="--html-in-header katex-header.html" $(CARGO) doc --no-deps

# The same pages with a local KaTeX, for a machine without network, e.g. after
# `npm install katex` in /tmp: make doc-offline KATEX_DIST=/tmp/node_modules/katex/dist
doc-offline:
	@test -f "$(KATEX_DIST)/katex.min.js" || { echo "KATEX_DIST must name a KaTeX dist/ directory holding katex.min.js (e.g. KATEX_DIST=/tmp/node_modules/katex/dist)" >&2; exit 2; }
	mkdir -p target
	sed -e 's#https://cdn.jsdelivr.net/npm/katex@[0-9.]*/dist#file://$(abspath $(KATEX_DIST))#' \
	    -e 's# crossorigin="anonymous"##' katex-header.html > target/katex-header-offline.html
	RUSTDOCFLAGS="--html-in-header $(CURDIR)/target/katex-header-offline.html" $(CARGO) doc --no-deps
