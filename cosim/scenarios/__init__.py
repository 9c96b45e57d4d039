"""What comes in: scenario TOML files (the bundled ones live here too), their config dataclasses, loader and writer."""
