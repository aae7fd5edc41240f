"""Data files shipped with the package: the paper's design and problem (TOML)."""
