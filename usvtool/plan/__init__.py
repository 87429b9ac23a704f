"""Global path planning: the path problem, optimizers, exact planners, benchmark functions."""
