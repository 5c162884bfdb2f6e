"""Numerics the models are built from: power laws and their exact integrals, quadrature, the
"paper" interaction's pole integral, a safeguarded monotone root-finder, input validation."""
