#!/usr/bin/env bash
# The API documentation with its dependencies, the math rendered by KaTeX without internet:
#
#   docs/doc.sh           # writes target/doc/ (the crate's pages: target/doc/jeffcott/index.html)
#   docs/doc.sh --open    # and opens them; any other `cargo doc` argument is passed on too
#
# KaTeX 0.16.11 is vendored in docs/katex/ (MIT, docs/katex/LICENSE; byte for byte the files
# docs/katex-header.html loads from the CDN with SRI hashes, as docs.rs shows the pages). It is
# copied to target/doc/katex/, where docs/katex/header.html finds it from every page through
# rustdoc's root path; the header is given by an absolute path because cargo documents each
# dependency from that dependency's own folder. Run from anywhere inside the repository.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
doc=${CARGO_TARGET_DIR:-target}/doc

# Copied first: `--open` opens the pages as soon as they are written.
mkdir -p "$doc/katex"
cp -R docs/katex/. "$doc/katex/"
# Encoded flags (separated by 0x1f): a clone's path may contain spaces. RUSTDOCFLAGS still counts.
read -r -a flags <<<"${RUSTDOCFLAGS:-}"
flags+=(--html-in-header "$root/docs/katex/header.html")
CARGO_ENCODED_RUSTDOCFLAGS=$(IFS=$'\x1f' && echo "${flags[*]}") cargo doc "$@"
