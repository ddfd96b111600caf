"""A user's constraint on a classic task (a benchmark task of benchmarks/multiplier_start.py):
CartPole-v1 with info["cost"] 1 on every step the cart stands right of ``bound`` (0.5; the track
ends at 2.4), so balancing to the time limit is possible on either side of the line and the
question is only whether the agent keeps left of it."""
import gymnasium as gym


class RightOfLine(gym.Wrapper):
    def __init__(self, env, bound=0.5):
        super().__init__(env)
        self.bound = float(bound)

    def step(self, action):
        obs, reward, terminated, truncated, info = self.env.step(action)
        info["cost"] = float(obs[0] > self.bound)
        return obs, reward, terminated, truncated, info


def make(bound=0.5):
    return RightOfLine(gym.make("CartPole-v1"), bound)


gym.register("CartPoleRightOfLine-v0", entry_point=make, max_episode_steps=500)  # as a user module registers its id
