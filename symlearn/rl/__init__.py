"""Small, readable RL algorithms used by learners and experiments."""
