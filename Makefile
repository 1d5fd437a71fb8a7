# Convenience targets; each runs the script of the same name (the README's commands).
.PHONY: demo test build deps test-asan bench
demo:      ; scripts/demo
test:      ; scripts/test
build:     ; scripts/install-deps && scripts/build
deps:      ; scripts/install-deps
test-asan: ; scripts/test-asan
bench:     ; scripts/install-bench-deps && scripts/build && benchmarks/compare
