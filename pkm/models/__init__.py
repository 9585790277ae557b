"""Runtime modules of pkm's mechanisms (registered in pkm.load)."""
