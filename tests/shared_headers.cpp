// The translation unit that builds the suites' precompiled header (tests/shared_headers.h).
