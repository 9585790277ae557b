"""Runtime modules of pkm's mechanisms, registered by name."""
