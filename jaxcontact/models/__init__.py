"""Contact models of the whole joint: the abstract interface and the load-controlled solve of
largest-spot models (`base`), the seed model (`xia2024`) and its comparators. Each model is one
file here plus one line in `jaxcontact.registry`."""
