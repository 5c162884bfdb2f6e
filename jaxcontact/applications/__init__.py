"""What is built on the stiffness: the load–approach curve, a driven mass on the joint, sharded
parameter sweeps, and chunked solves of long load sweeps."""
