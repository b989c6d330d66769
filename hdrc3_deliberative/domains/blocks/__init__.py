"""Planning domain files shipped with hdrc3_deliberative (data package)."""
