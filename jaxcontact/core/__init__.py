"""The problem and its solution: the parameters and their domain, the scene, the units, the
default scene, load control (`solve`), the `Solution` and its status codes."""
