"""Demo ``rm``: a reward machine inferred from Stack-2 videos, drawn with its prototypes, and a short DQRM run.

The scripted demonstrator stacks red on green once; the front camera's frames give the machine
(thesis section 7.4, data-derived eps / min samples / kappa), written with its labeling, prototype
images, DOT drawing and report; the machine is compared with the ground truth; DQRM then learns to
stack from the top-down images with the machine's shaped reward (quick settings: a few episodes).
"""

from __future__ import annotations

from symlearn.demo.registry import DemoContext, Pipeline, Section


def run(context: DemoContext) -> Section:
    from symlearn.recipes.block_rewards import block_setup
    from symlearn.envs.rendered_blocks.demonstrator import demonstrations
    from symlearn.learners.reward_machines.compare import isomorphic
    from symlearn.learners.reward_machines.machine_building import machine_from_edges
    from symlearn.learners.reward_machines.report import transitions_table, write_results
    from symlearn.learners.reward_machines.rm_inference import RewardMachineInference
    from symlearn.rendering import dot_available, render_dot
    from symlearn.rl.dqrm import DQRMConfig, train_dqrm

    demos = demonstrations("stack-2", seed=context.seed)
    learner = RewardMachineInference().fit(demos.front)
    target = context.path("rm", "stack2.json")
    files = [str(p.relative_to(context.out_dir)) for p in write_results(learner, target, title="Stack-2",
                                                                         source="scripted Stack-2 video")]
    if dot_available():
        files.append(str(render_dot(target.with_suffix(".dot").read_text(), target.with_suffix(".svg"))
                         .relative_to(context.out_dir)))
    s = demos.task.truth_structure()
    truth = machine_from_edges(s["propositions"], s["edges"], s["initial"], s["accepting"])
    same = isomorphic(learner.machine_, truth)

    setup = block_setup("stack-2", "inferred", seed=context.seed)
    episodes = 6 if context.quick else 40
    result = train_dqrm(setup.env_fn, setup.machine, setup.labeling, setup.prototypes,
                        demonstrations=setup.demonstrations, seed=context.seed,
                        config=DQRMConfig(episodes=episodes, learning_rate=1e-3, updates_per_episode=8,
                                          eval_every=3 if context.quick else 5))
    first = next((h.episode for h in result.history if h.success == 1.0), None)
    metrics = learner.result_.metrics
    lines = [f"One demonstration ({metrics['frames']} frames, front camera 64 px, lighting jitter and noise).",
             "", "![prototypes](rm/stack2.prototypes.png)", "",
             f"Machine: {learner.machine_.n_states} states ({metrics['clusters']} clusters), isomorphic to the "
             f"ground truth: {'yes' if same else 'no'}; eps {learner.eps_:.3g}, min samples {learner.min_samples_}, "
             f"kappa {learner.kappa_:.3g} (all derived from the data); {learner.result_.timings['total']:.2f} s.", ""]
    lines += [f"* u{u} --{read}--> u{v}, shaped reward {reward:.3g}"
              for u, read, v, reward in transitions_table(learner.shaped_machine_)]
    lines += ["", f"DQRM on the inferred machine, {episodes} episodes ({result.seconds:.0f} s): first greedy success "
                  f"at episode {first}; last evaluation: success {result.history[-1].success:.0f}, placement error "
                  f"{result.history[-1].placement_error:.3f}."]
    if dot_available():
        lines += ["", "![machine](rm/stack2.svg)"]
    figures = {"states": learner.machine_.n_states, "isomorphic_to_truth": same, "eps": learner.eps_,
               "kappa": learner.kappa_, "dqrm_episodes": episodes, "dqrm_first_success": first,
               "dqrm_curve": [h.as_dict() for h in result.history]}
    return Section("Reward machine from Stack-2 videos, and DQRM on it", "\n".join(lines), figures, files)


PIPELINE = Pipeline("rm", "Reward machine from images (Stack-2) and DQRM", run)
