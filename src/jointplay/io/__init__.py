"""Input and output at the edges: configuration files, result files, output folders."""
