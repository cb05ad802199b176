"""How the study trains its agents: the paper's literal set-up, ours, and the factors between them.

The paper fixes the algorithm (discrete SAC, Tables 2-3) and the tasks, but some of what decides
whether an agent learns is either left open (the control period, the obstacle-avoidance task,
the thrust calibration) or stated twice in ways that disagree (Table 3 updates 10 times after each
episode; section 3.2's text updates "at each step"). A :class:`TrainingSetup` names every such
choice as one factor; :data:`PAPER` is the paper read literally and :data:`OURS` is the set-up
the study uses by default, each departure measured by the ablation
(:mod:`sb3_pnn.reproduce.ablation.catalog`, ``docs/ablation/report.md``).

Factors:

* ``vehicle``: the BlueROV2 parameter set (``rov_envs``' ``vehicle=``): ``"uuv_simulator"``,
  the model of the paper's Gazebo set-up (section 4.1), or ``"wu2018"``.
* ``control_period``: seconds per environment step (the paper does not give it).
* ``updates``: ``"episode:N"``: N gradient steps of batch 256 after every episode (Table 3,
  "Number of Samples per Episode 10"); ``"step:K"``: one gradient step every K environment
  steps (K = 1 is section 3.2's "At each step, 256 samples ... are used to update");
  ``"step:KxG"``: G gradient steps every K environment steps.
* ``prior_updates``: the update schedule of the source columns' runs (DiscreteSAC on the
  path-following and obstacle-avoidance tasks), when it should differ from ``updates``
  (empty: the same). A source column is trained once and reused by every agent and seed, so
  more updates there cost little beside the transfer runs.
* ``oa_updates``: the update schedule of the obstacle-avoidance column's runs alone, when it
  should differ from ``prior_updates`` (empty: the same). The avoidance task among random fields
  is the hardest source task, and only SPNN reads its column, so its schedule can change
  without retraining the path followers, PNN or SAC-Multi.
* ``oa_gamma``: the discount factor of the obstacle-avoidance column's runs (None: Tables 2-3's
  0.99, every run's). The discount is per decision, so 0.99 looks about 1 / (1 - gamma) =
  100 steps ahead: 100 s at the 1.0 s control period (50 s at 0.5 s, where an avoidance
  episode lasts up to 120 s): from its start the +200 of arriving is then worth less than a
  tenth of a collision's -200 met in the next seconds, and a column can settle on crawling
  until the time limit. At 0.5 s, 0.995 looks as far ahead in seconds as 0.99 does at 1.0 s.
* ``pf_sine_gamma``: the discount factor of the sine path-following column's runs (None:
  Tables 2-3's 0.99). That column flies parallel to its path a metre or two beside it, the LOS
  course pointing back, rather than turning in: a turn now instead of one step later gains
  about one step's reward, (1 - gamma) of Q's scale, which at 0.99 is 0.1 % of Q and easily
  lost in the critic's error. A shorter discount widens that gap relative to Q, and also
  weighs the progress of the next few steps more against the charge for riding off the path.
* ``spnn_gamma``, ``pnn_gamma``: the discount factor of SPNN's, PNN's planning runs (None:
  Tables 2-3's 0.99; PNN's n-step targets discount with it); ``pnn_gamma_sine``: PNN's on the
  sine path (None: ``pnn_gamma``'s). A planning episode lasts 150-400 s: 1.5 to 4 times what
  0.99 looks ahead at 1.0 s per decision, three to eight times at 0.5 s.
* ``batch_size``: samples per gradient step (section 3.2: "256 samples ... are used to
  update"); ``prior_batch_size``: that of the source columns' runs, when it should differ
  (0: the same), as ``prior_updates`` is to ``updates``.
* ``train_start_noise``: training episodes start from a perturbed pose (1 m, 5 deg, the
  evaluation's noise) instead of the paper's exact start point (0, 0).
* ``pf_start_spread``: with ``train_start_noise``, the path-following source columns train from
  a start pose perturbed by this multiple of (1 m, 5 deg) instead (None: 1), so that the column
  learns to come back to the path from as far as the avoidance column leaves the vehicle.
  ``planning_start_spread`` is the same multiple for the learners' planning tasks (None: 1).
* ``learner_sonar_noise``: std (m) of Gaussian noise on every sonar return in the learners'
  planning-task training episodes only (rov_envs' ``sonar_noise``; their validation checks, the
  evaluation and the source columns read the sonar noise-free; 0: none, the paper). A
  randomization of the observation, so that a learner that trains on one fixed layout does
  not key its avoidance to that layout's exact readings.
* ``motion_obs``: the observation also holds sway v and yaw rate r (``motion_obs=True``); the
  paper's state is o = [a_c, g, d_1..d_q] (section 4.2.2).
* ``success_reward``: reward on reaching the target (0 = eq. 17-21 literally).
* ``progress_weighted``: r_c of eq. 18/19 is paid in proportion to progress along the path
  (``progress_weighted=True``; not in the paper). Literally, eq. 18 pays about +1 per step near
  the path whether the vehicle advances or not, so with gamma = 0.99 staying put in front of an
  obstacle is worth more than passing it (measured: agents loiter to the time limit).
  ``progress_along``: the direction of that progress, ``"path"`` (the path's tangent, ours) or
  ``"course"`` (the LOS course, from which a_c is measured). Along the tangent, a vehicle
  running parallel to the path 6-10 m off is paid as much as one turning back along the LOS
  course, so a policy can hold that offset; along the course the way back is paid in full
  (docs/ablation section 84). Every eq. 18/19 task reads it (the source columns' and the
  learners'); the obstacle-avoidance task's progress reward does not.
  ``planning_progress_along`` (None: ``progress_along``'s) sets it for the learners' planning
  tasks alone, the source columns keeping ``progress_along``'s.
  ``pf_progress_weighted`` (None: ``progress_weighted``'s): the path-following source columns'
  own choice, off giving them eq. 18/19 as written (beside the success reward), which pays
  pointing along the LOS course atan(g / Delta) / pi more than running parallel to the path
  (docs/ablation section 86). The learners keep ``progress_weighted``.
* ``net_arch``: hidden layers of every actor and critic column (Table 2: [255, 255]).
  ``pnn_net_arch``: those of PNN's new column alone (empty: ``net_arch``'s); its frozen prior
  keeps its own, and eq. 13's lateral adapters map the prior's widths to the new column's.
* ``target_entropy_ratio``: the entropy the temperature alpha is tuned toward, as a fraction of
  the uniform policy's log|A| (the paper gives only alpha's initial value, 0.2, Table 3).
  ``learner_target_entropy_ratio`` gives the four learners' runs their own fraction (None:
  ``target_entropy_ratio``; the source columns always read ``target_entropy_ratio``): at 0.5 the
  policy keeps about a 50/50 mixture of two actions in every state.
* ``pnn_lateral_init``: PNN's lateral connections (eq. 13) are scaled by a learned scalar per
  lateral, as in Rusu et al. (2016); this is its initial value. 1 starts from eq. 13 as written;
  0 starts the new column as a network without priors (SAC-Single) that learns how much of the
  prior's features to take. Only PNN runs read it. ``pnn_lateral_init_sine`` gives the sine
  path a value of its own (``None``: ``pnn_lateral_init`` on both paths).
* ``pnn_critic_priors``: on which planning paths PNN's critics (Q-networks) are progressive
  columns that read the frozen prior's critic too, as Algorithm 1 transfers Q_theta along with
  pi_phi (written for SPNN): ``"both"``, ``"straight"``, ``"sine"`` or ``"neither"`` (``--set``
  also takes ``true`` for both and ``false`` for neither). Elsewhere the critics are plain
  networks and only the actor reads the prior (``ProgressivePolicy(critic_priors=False)``), as
  section 3.2 names only the policy pi_phi_lambda as PNN's first column. Only PNN runs read it.
* ``pnn_start_as_prior``: on which planning paths (values as ``pnn_critic_priors``) the PNN's
  networks start as their prior: before any update the actor outputs the prior's logits and
  each critic that reads the prior's critic its Q-values; the new column's own output layer
  starts at zero and the output laterals copy the prior's output layers
  (``start_as_prior=True``, :meth:`sb3_pnn.progressive.columns.ProgressiveNet.start_as_priors_`).
  Off: the new column starts at random, as in Rusu et al. (2016) and, by its silence, the paper.
  SAC-Multi, the paper's other way to reuse the prior, starts from its weights too. Only PNN
  runs read it. ``spnn_start_as_prior`` (a bool) does the same for the SPNN, whose output then
  starts as the gate-selected prior's.
* ``pnn_init_from_prior``: on which planning paths (values as ``pnn_critic_priors``) the PNN's
  new column starts as a copy of the prior's column, actor from actor and critics from critics
  (``init_from_prior=True``): section 3.1's "the parameters of the second column are usually
  initialized with Theta^(1) or randomly"; section 3.2 and Rusu et al. (2016) start it at random
  (off). With the laterals' scale at 0 the PNN then starts as SAC-Multi does, keeping the frozen
  prior beside it. ``spnn_init_from_prior`` (values as ``pnn_critic_priors``) starts the SPNN's
  new column as a copy of its first, the path-following, prior.
* ``pnn_avoidance_column``: on which planning paths (values as ``pnn_critic_priors``) PNN
  reads the obstacle-avoidance column beside its path-following one, ungated: eq. 13 with
  every earlier column, as Rusu et al. (2016) and the paper's Figure 3 draw it, where the
  paper's PNN is dual-column (section 3.2: the path follower alone) and only SPNN gets the
  avoidance column, through its gate. The path-following column stays the reference of
  ``pnn_start_as_prior`` and ``pnn_prior_kl`` (``ProgressivePolicy(reference_prior=0)``); the
  avoidance column's output lateral starts at zero. It separates what SPNN gains from its
  second column from what it gains from its gate. Only PNN runs read it.
  ``pnn_near_prior_kl`` (values as ``pnn_critic_priors``; it acts on paths where PNN reads
  the avoidance column and ``pnn_prior_kl_clearance`` is set): on the samples nearer an
  obstacle than the clearance, and inside SPNN's corridor bound ``spnn_gate_corridor`` where
  set, PNN's KL term pulls toward the avoidance column instead of leaving them out
  (``ProgressivePolicy(near_reference_prior=1)``): the switch of eq. 15 picks the reference of
  the regularizer, not the network's input; not in the paper. ``pnn_near_corridor`` (a fraction
  of d_L in (0, 1]; None: ``spnn_gate_corridor``'s) gives the near reference a corridor bound
  of its own, ``pnn_near_corridor_sine`` (None: ``pnn_near_corridor``'s) the sine path's.
  Ours: 0.6 on the sinusoid, whose 15 m corridor the avoidance column's detours overran
  (docs/ablation section 68), SPNN's 0.9 on the straight path.
* ``spnn_d_th``: SPNN's switch distance d_th in metres (eq. 15; the paper's 12.5 m was "set
  after a number of experimental trials"): the obstacle-avoidance prior's laterals feed the new
  column while the nearest obstacle is nearer. Only SPNN runs read it; ``spnn_d_th_sine``
  gives the sine path a distance of its own (``None``: ``spnn_d_th`` on both paths).
* ``spnn_gate``, ``spnn_gate_temperature``: how SPNN's selector weighs its two priors
  (:mod:`sb3_pnn.progressive.gates`): ``"hard"``, eq. 15's switch at d_th; ``"soft"``, the
  avoidance prior's weight sigmoid((d_th - d) / T) with T = ``spnn_gate_temperature`` metres,
  so that the laterals (and the KL term's prior, a mix of the two) blend where the nearest
  obstacle is about d_th away instead of flipping there; ``"learned"``, an A2T-style softmax
  gate trained with the network that owns it (the paper's future work). Only SPNN runs read
  them; the temperature only with the soft gate. ``spnn_gate_sine`` gives the sine path a
  gate of its own (``None``: ``spnn_gate`` on both paths). Ours: the switch on the straight
  path, the soft gate (T = 2 m) on the sinusoid, whose 15 m corridor leaves no room for the
  avoidance prior's detours once the switch has handed it the laterals.
* ``spnn_gate_corridor``: with a hard or soft gate, the fraction c of the corridor half-width
  d_L (eq. 21's off-path edge) beyond which SPNN's selector hands the laterals to the path
  column whatever the sonar reads (|g| / d_L >= c). ``None`` (the paper): the distance alone
  decides. Ours: 0.9. On the straight path (d_L = 30 m) few detours reach it; on the sinusoid
  (15 m) it ends the avoidance column's detours before the corridor's edge ends the episode.
* ``spnn_switch_memory``: H (m), a memory for SPNN's hard switch: its planning runs observe
  rov_envs' ``obstacle_latch=(d_th, d_th + H)`` part and the avoidance column keeps control
  from a reading within d_th until one beyond d_th + H (``SelectivePolicy(gate_latch_key=
  "latch")``). None (the paper): eq. 15's switch without memory. Only SPNN runs on a path
  whose gate is the hard switch read it.
* ``spnn_play_memory``: H (m), the same memory at evaluation only: SPNN's runs train and keep
  their policy with eq. 15's switch, and the study evaluates them through
  :class:`sb3_pnn.progressive.SwitchMemory` (the avoidance column keeps control until the
  nearest reading is beyond d_th + H). None (the paper): evaluated as trained. Ours: 10 m
  (docs/ablation section 47). Only SPNN runs on a path whose gate is the hard switch read it.
* ``spnn_play_no_reversal``: on which planning paths (values as ``pnn_critic_priors``) the study
  evaluates SPNN's runs through :class:`sb3_pnn.evaluation.NoReversal`: where the policy's
  action turns to the side opposite to the step before's, "Go straight" is played for that step
  (training and the kept policy unchanged). Among a row of obstacles the soft gate's policy can
  alternate Turn left 1 and Turn right 1 with confident probabilities, creeping until the time
  limit. "neither" (the paper): evaluated as trained. Ours: the sinusoid (docs/ablation section
  50: +10.8 and +10.4 points of drawn fields on seeds 0-4 and fresh seeds 5-9; on the straight
  path, whose switch plays with ``spnn_play_memory``, -3.6).
* ``pnn_play_no_reversal``: the same for PNN's runs. Ours: the sinusoid (docs/ablation section
  67: +8.0 points of drawn fields over ten seeds, once PNN reads the avoidance column; the
  time limits of its creeping runs gone). Section 50 had measured +3.6 for the PNN that read
  the path column alone, short of its rule.
* ``learners_play_no_reversal``: the same for every learner's runs on the named paths (PNN,
  SAC-Single, SAC-Multi and SPNN), so that Figure 20's learners can be compared played alike.
  "neither" in both set-ups: only SPNN's validation rule passed (docs/ablation section 50).
* ``spnn_sigma``, ``spnn_own_weight``: the weights sigma (of the selected prior's lateral
  input) and tau (of the new column's own input) of eq. 15, "both set to be 0.5" in the paper.
  With both at 1 the SPNN is eq. 13's PNN whose laterals come from the gate-selected prior
  only. Only SPNN runs read them.
* ``spnn_prior_kl``, ``pnn_prior_kl``: weight beta of KL(pi || pi_0) in the actor's loss, pi_0
  the frozen priors' own policy (the SPNN's gate-selected prior; ``prior_kl`` of
  :class:`sb3_pnn.ProgressivePolicy`): the new policy stays near what its priors do where
  reward does not pay for more (not in the paper: 0; ours: 1 for both). Only SPNN / PNN runs
  read them. ``pnn_prior_kl_clearance`` (m) limits PNN's term to the samples whose nearest
  obstacle is farther than it, where its path-following prior, which knows no avoidance,
  applies (``prior_kl_clearance`` of :class:`sb3_pnn.ProgressivePolicy`; None: every sample;
  ours: d_th, 12.5 m).
* ``spnn_off_path_kl``: weight beta_off of the same KL term over off-path copies of each of
  SPNN's minibatches (``off_path_kl`` of :class:`sb3_pnn.ProgressivePolicy`, module
  :mod:`sb3_pnn.progressive.off_path`): the copies' path part is redrawn 0.3-1 corridor
  half-widths off the path, their sonar clear, so the gate selects the path-following prior and
  the new column is pulled toward it where the learner's own replay seldom goes (not in the
  paper: 0). ``spnn_off_path_kl_sine`` gives the sine path a weight of its own (None:
  ``spnn_off_path_kl``'s). Only SPNN runs read them. Ours: 1 on the sinusoid (docs/ablation
  section 59: +8.0 points of drawn fields over ten seeds; the straight path's runs already
  pass theirs and were not trained with it). ``pnn_off_path_kl``: the same for PNN's runs,
  whose reference is the path-following column (not in the paper: 0); ``pnn_off_path_kl_sine``
  gives the sine path a weight of its own (None: ``pnn_off_path_kl``'s). ``pnn_clear_kl``
  (``pnn_clear_kl_sine`` for the sine path, None: ``pnn_clear_kl``'s): the weight of PNN's KL
  term over copies of each minibatch that keep the path part and read a clear sonar, where the
  path-following column is the reference (not in the paper: 0). ``spnn_clear_kl``
  (``spnn_clear_kl_sine``, None: ``spnn_clear_kl``'s) does the same for SPNN, whose gate selects
  the path-following prior on the copies (not in the paper: 0; ours: 1 on SPNN's sine runs,
  beside ``spnn_obstacle_kl_sine=0.5``, sections 81-82). ``pnn_obstacle_kl``,
  ``spnn_obstacle_kl`` (``_sine`` alike): the weight of the KL term over copies of each
  minibatch whose sonar also reads 1-3 cylinders drawn around the vehicle, of the avoidance
  task's own sizes (:mod:`sb3_pnn.progressive.obstacle_copies`); where one lies nearer than the
  clearance, the reference is the avoidance column (PNN's near reference, SPNN's gate), so the
  new column is held to that column among obstacle patterns its one training layout never
  shows (not in the paper: 0). The copies are states made up for the regularizer, not episodes:
  no layout is drawn and no reward is paid on them. Ours: 0.5 on PNN's sine runs (docs/ablation
  sections 79-80: drawn fields +2.9 points over fifteen seeds, routes within 10 %), and on
  SPNN's sine runs 0.5 beside ``spnn_clear_kl_sine=1`` (sections 81-82: the clear-sonar term
  brings SPNN's sine routes closer, the drawn-obstacle term pays back its cost among drawn
  obstacles).
* ``spnn_n_steps``, ``pnn_n_steps``: the length n of the critics' returns, y = sum_{k<n}
  gamma^k r_{t+k} + gamma^n V(s_{t+n}) (``n_steps`` of ``DiscreteSAC``; the paper's SAC, and
  Christodoulou's, bootstrap after one step: 1). Only SPNN / PNN runs read them.
  ``pnn_n_steps_sine`` gives PNN's runs on the sine path their own n (None: ``pnn_n_steps``).
* ``pf_n_steps``: the same return length n for the two path-following source columns (not the
  avoidance column, not the learners). Eq. 18/19 pay for coming back to the path only after a
  turn and its counter-turn; an n-step return carries that pair's reward into one target.
* ``spnn_action_smoothness``, ``pnn_action_smoothness``: weight lambda of the temporal
  smoothness term lambda * E[KL(pi(.|s_t) || pi(.|s_t+1))] in the actor's loss (CAPS, Mysore
  et al. 2021; ``action_smoothness`` of :class:`sb3_pnn.ProgressivePolicy`): it discourages
  turning left on one control step and right on the next (not in the paper: 0). Only SPNN /
  PNN runs read them.
* ``goal_obs``: the "goal" part (the heading deviation from the bearing to the goal, a route
  point ``goal_distance`` m ahead) is observed: by the obstacle-avoidance task instead of the
  "path" part, and by the planning tasks beside it, so that SPNN's avoidance column reads the
  quantity it was trained on (off: every task observes the paper's [a_c, g]).
* ``pnn_goal_obs``: with ``goal_obs``, PNN's planning runs observe the goal part too (off: PNN,
  whose only prior is a path follower, observes the planning tasks as the paper states them;
  the tasks' rules, the heading rule included, are the same for every learner).
* ``goal_distance``: how far ahead along the route the goal lies (None: the target point).
* ``exploration_epsilon``: the learners (not the source columns) replace each training
  action by a uniformly drawn one with this probability (``exploration_epsilon`` of
  ``DiscreteSAC``): a softmax policy almost never tries an action whose Q-value lies far below
  the best, so that value is never corrected (not in the paper: 0).
  ``pnn_exploration_epsilon`` gives PNN's runs their own epsilon (None: ``exploration_epsilon``),
  ``pnn_exploration_epsilon_sine`` PNN's runs on the sine path theirs (None: PNN's).
* ``mirror_augmentation``: the learners (not the source columns) replace half of each
  minibatch by its left-right mirror image (``DiscreteSAC(mirror=rov_envs.LEFT_RIGHT_MIRROR)``,
  :mod:`sb3_pnn.common.mirror`): the tasks are mirror-symmetric, so a mirrored transition is a
  true one of the mirrored task, and a learner that trains on one fixed layout also learns it
  with left and right swapped (not in the paper: off). ``oa_mirror`` does the same for the
  avoidance column's runs alone: trained on random fields it learns to detour to one side of
  its start-goal line on nearly every episode, though the task has no preferred side.
* ``sonar_span`` (degrees, centred ahead), ``sonar_sectors``: the sonar's span S and its q
  sectors (section 4.2.2; the paper gives neither: 180 and 9). The nearest reading is also
  eq. 15's d; with a span under 360 degrees it depends on the heading, and an obstacle beside
  the vehicle leaves the view when it turns away.
* ``heading_rule``: what the planning tasks' failure |a_c| >= pi/2 (eq. 21) reads: ``"path"``,
  a_c of the LOS course as the paper; ``"goal"``, the deviation from the goal's bearing.
* ``los_lookahead``: the LOS lookahead Delta (m) of eq. 16 in every task (the paper gives none;
  rov_envs' 5 m; the obstacle-avoidance task, which measures a_c from the goal, ignores it):
  a_c, which the "path" part observes and eq. 18/19 charge, is measured from the course toward
  the path point Delta ahead, so a vehicle d m off the path reads atan(d / Delta) of heading
  error while parallel to it.
* ``oa_layout``: the obstacles of the obstacle-avoidance source task: ``"avoidance"``, its own
  (2-4 cylinders of 1.5 m near the start-goal line), or ``"scatter"`` (a random field of random
  density and size, :mod:`rov_envs.sim.layouts`, none of the new layouts' generators; ours:
  the avoidance column learns among obstacles of many sizes and spacings, as SPNN meets them
  within d_th).
* ``oa_corridor``: the corridor half-width d_L (m) of the obstacle-avoidance source task's
  training episodes, |g| < d_L around its start-goal line (None: the task's 30 m, the straight
  tasks' d_L). The planning tasks it is composed into keep the vehicle within 30 m (straight)
  or 15 m (sine) of their route (section 4.2.1); an avoidance column trained within 30 m may
  go round a whole field of obstacles where the sine task's corridor allows no such detour.
* ``oa_time_limit``: the time limit (simulated s) of the obstacle-avoidance source task's
  training and validation episodes (None: the task's own, twice its 60 m at 1 m/s = 120 s).
  A column that may take 120 s can cross its field at half the speed of "Go straight"; a
  shorter limit keeps only the columns (and checks) that pass obstacles at pace, which is the
  pace SPNN's new column inherits within d_th.
* ``oa_budget``: the obstacle-avoidance source column's training episodes, as a multiple of
  the study budget's (1: the budget's 300; its validation checks keep their schedule, so a
  longer run is the same run continued, with more checks to keep one from). The avoidance
  skill is what SPNN's gate hands the vehicle to near obstacles, so a column that has not
  converged caps how often SPNN passes a field of them. Ours: 2 (with ``spnn_play_memory``,
  docs/ablation section 47).
* ``pf_sine_budget``: the sine path-following column's training episodes, as a multiple of the
  budget's (1: the budget's 150), its checks on their schedule as ``oa_budget``'s. At 150
  episodes some columns are still improving at their last check (one of ten does not yet pass
  its task), and the learners on the sinusoid take over the route their column keeps. Ours: 2
  (docs/ablation sections 54 and 57).
* ``oa_offset_obs``: the avoidance column's "goal" part also holds its signed distance from
  the route, g / d_L (``rov_envs``' ``goal_offset``), on its own task (its start-goal line) and,
  so that it reads there what it was trained on, in the planning runs of every learner that
  reads that column (SPNN's, and PNN's where ``pnn_avoidance_column`` acts); no other run
  changes. Without it a column trained within a corridor (``oa_corridor``) cannot see how close
  to the corridor's edge a detour has taken it.
* ``prior_candidates``: each source column is trained this many times (training seeds
  ``k * set + j``, j < k, for the column set ``set``: 0 for the shared one) and the candidate
  that does best on validation episodes of its own task (success rate, then mean return, of its
  kept check) becomes the column every agent reads. 1: one training run per column (the paper
  says nothing of how its columns were chosen). A column is trained once and read by every
  transfer run, and one draw of it decides much of what they do; keeping the best of k on the
  source task's own validation episodes removes a poor draw at the cost of k - 1 more runs.
* ``prior_retries``: a source column none of whose validation checks passes a single episode
  is trained again from another seed (``seed + 1000 * i``), up to this many times; a column
  that passed a check is kept as it is. 0: never (a column that never reaches its target in
  training is the prior of its seed's learners all the same; the study's report names it).
* ``pf_validation_every``: training episodes between two validation checks of the two
  path-following columns (the avoidance column and the learners check every
  ``VALIDATION_EVERY``). A column's route swings from check to check (the same run can keep
  its path within 0.1 m at one check and 4 m at a later one); checks are cheap (a batch of
  episodes without updates), and a finer grid keeps a column nearer its best moment. Model
  selection only: training is unchanged.
* ``planning_layout``: the obstacles the planning agents train on: ``"fixed"``, the paper's
  (section 4.3.3: trained on the original tasks only), or ``"scatter"`` (drawn afresh every
  training episode around the route; beyond the paper, reported apart). Evaluation always runs
  the paper's tasks and the new layouts.
* ``keep_best``: the run keeps the policy that did best on validation episodes of its own task
  (every ``VALIDATION_EVERY`` training episodes, ``VALIDATION_EPISODES`` episodes under start
  noise, seeds from :data:`sb3_pnn.common.callbacks.VALIDATION_SEED`, apart from the evaluation's),
  as the RL Zoo's ``EvalCallback`` does; off: the policy at the end of the budget (the paper
  does not say which policy it reports).
* ``keep_best_drawn``: episodes per validation check that the learners (SPNN, PNN, SAC-Multi,
  SAC-Single) also run on their own path among obstacles drawn afresh every episode (the
  ``scatter`` generator, none of the new layouts'; seeds from
  :data:`sb3_pnn.common.callbacks.DRAWN_VALIDATION_SEED`); a check then ranks by its own-task
  success, then its success among those obstacles, then its return. 0: own-task checks only.
  Model selection on a validation distribution; training is unchanged.
* ``keep_best_by``: what ranks the learners' validation checks of equal success: ``"return"``
  (the larger mean return; ours), ``"route"`` (the smaller mean abs(g) on the same episodes:
  the route kept closer) or ``"time"`` (the shorter mean time to the target: the faster
  crossing). Eq. 20's obstacle term pays for detours that keep 8 m from every
  obstacle, so the return prefers checks that leave the route wider. The source columns keep
  ranking by return. Model selection on the training task; training is unchanged.
  ``spnn_keep_best_by_sine`` ranks SPNN's sine runs' checks (None: ``keep_best_by``). Ours:
  ``"last"``, the latest check whatever its success, that is the last policy: SPNN's sine route
  narrows as it trains while its return peaks earlier, and on seeds 0-4 and fresh seeds 15-19
  the last policy keeps the route 14 % / 11.5 % closer at 6-9 % less return (docs/ablation
  section 103). Without ``keep_best`` every run keeps its last policy anyway.
* ``keep_best_route_bound``: a mean abs(g) in metres: of the learners' validation checks of
  equal success, those that keep their route within it rank above those that leave it, and
  ``keep_best_by`` chooses within each group (None: no bound). The return-best check keeps
  whatever route eq. 20 pays for, which on the planning tasks is wider than a route-keeping
  mark (docs/ablation section 100); the bound keeps the best return among the routes wanted,
  where ranking by route alone keeps the closest check whatever it earns. Model selection on the
  training task; training is unchanged. Without ``keep_best`` there are no checks, and the bound
  changes nothing. Ours: none. 2.0 m, the route mark of the planning tasks, brings the sine
  routes 13-19 % closer on seeds 0-4 at a level drawn-field success, but on fresh seeds 5-9 one
  straight run loses 40 points of drawn fields (docs/ablation section 101).
  ``keep_best_route_bound_sine`` gives the sine path's runs a bound of their own (None:
  ``keep_best_route_bound``'s), as on the path whose planning route misses the mark
  (docs/ablation section 102).
* ``keep_best_also``: further rankings of the learners' checks, comma-separated (``"route,last"``;
  empty: none). Each keeps its own best policy of the same training beside the one kept, saved
  in the run folder as ``model_by_<ranking>.zip`` (``model.zip`` stays the kept policy), so that
  rankings are compared on one training per run (``tools.fresh_route --kept-by``,
  ``tools.drawn_layouts --kept-by``). A measurement option: training and the kept policy are
  unchanged. Ours: none.
* ``prior_keep_best_by``: what ranks the source columns' validation checks of equal success:
  ``"return"`` (ours) or ``"discounted"``, the larger mean discounted return sum_t gamma^t r_t,
  what SAC maximises (the other rankings of ``keep_best_by`` are taken too). With r_c paid in
  proportion to progress the undiscounted return pays a path follower as much for creeping along
  the path with alternating turns as for following it at full speed, and the learners that read
  a creeping column creep too; the discount charges for the pace. Model selection on the source
  tasks; training is unchanged.
* ``prior_candidates_pf_straight``, ``prior_keep_best_by_pf_straight``: the same two choices
  for the straight path-following column alone (None: as the other columns), which only the
  learners of the straight path read; the sine column and the avoidance column keep
  ``prior_candidates`` and ``prior_keep_best_by``. The best of two straight columns ranked by
  the discounted return replaces a column that creeps along the line with one that follows it
  at full pace as closely, where on the sinusoid the faster candidates keep a wider route
  (docs/ablation/README.md, sections 32-34).
* ``planning_obstacle_penalty``: weight of eq. 20's r_v (-2 within 8 m, -4 within 5 m of an
  obstacle's surface, per step) in the learners' planning tasks, training and evaluation (1: the
  paper's; 0: only eq. 21's collision charges for closeness). The source columns' tasks keep
  the paper's. The term pays for detours that keep 8 m from every obstacle.
* ``planning_arrival_gate``: metres (0: none, the default): the learners' planning tasks, in
  training and evaluation, and the baselines' evaluation, count the end of the path as arrival
  only within this distance of the target point (rov_envs' ``arrival_gate``); farther off it
  is a failure, ``missed_target``. The paper's vehicle must "avoid the obstacle and return to
  the set path to complete the task" (section 4.2.1); without the gate, passing the path's end
  anywhere inside the 30 m corridor counts as success. ``pf_arrival_gate`` is the same gate
  for the path-following source columns' tasks (training and evaluation): their episodes start
  metres off the path (``pf_start_spread``), and the gate pays the way back, which eq. 18
  weighted by progress along the path barely does (docs/ablation sections 84-90).
"""

from __future__ import annotations

import copy
import json
import math
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, fields, replace
from typing import Any

from rov_envs.physics.guidance import DEFAULT_LOOKAHEAD, LOOKAHEAD_RANGE
from rov_envs.physics.params import VEHICLES
from rov_envs.sim.config import PROGRESS_DIRECTIONS
from rov_envs.sim.symmetry import LEFT_RIGHT_MIRROR
from sb3_pnn.common.callbacks import RANKINGS, VALIDATION_EPISODES, VALIDATION_EVERY
from sb3_pnn.common.checks import is_finite_number
from sb3_pnn.dsac.dsac import DEFAULT_TARGET_ENTROPY_RATIO, PAPER_BATCH_SIZE, PAPER_GAMMA
from sb3_pnn.progressive.selective_policy import (
    DEFAULT_PRIOR_KL,
    PAPER_D_TH,
    PAPER_OWN_WEIGHT,
    PAPER_SIGMA,
)

#: The start-pose noise of training episodes when ``train_start_noise`` is on: the evaluation
#: library's default (sb3_pnn.evaluation.DEFAULT_START_NOISE), 1 m and 5 degrees.
TRAIN_START_NOISE: tuple[float, float] = (1.0, math.radians(5.0))
#: Keywords of :meth:`TrainingSetup.train_env_kwargs` that perturb training episodes only: a
#: run's validation checks play its training task without them, as the evaluation does.
TRAINING_ONLY_ENV_KWARGS: tuple[str, ...] = ("start_noise", "sonar_noise")


def validation_env_kwargs(train_kwargs: dict[str, Any]) -> dict[str, Any]:
    """A run's training env keywords as its validation checks play them: without the
    training-only perturbations (the checks apply the evaluation's start noise)."""
    return {k: v for k, v in train_kwargs.items() if k not in TRAINING_ONLY_ENV_KWARGS}


#: Uniformly random steps before the first update, for every set-up and agent alike: one batch.
LEARNING_STARTS = 256


def parse_updates(updates: str, name: str = "updates") -> tuple[tuple[int, str], int]:
    """``(train_freq, gradient_steps)`` of DiscreteSAC for an ``updates`` string:
    ``"episode:N"``, N gradient steps after each episode; ``"step:K"``, one every K environment
    steps; ``"step:KxG"``, G every K steps (``"step:1x2"`` keeps a 0.5 s schedule's updates per
    simulated second at a 1.0 s control period)."""
    kind, _, number = str(updates).partition(":")
    expected = (
        '"episode:N" (N updates after each episode), "step:K" (1 update every K steps) or '
        '"step:KxG" (G updates every K steps)'
    )
    every, times, count = number.partition("x") if kind == "step" else (number, "", "")
    try:
        n = int(every)
        steps = int(count) if times else 1
    except ValueError:
        n = steps = 0
    if kind not in ("episode", "step") or n < 1 or steps < 1:
        raise ValueError(f"{name}={updates!r} is not allowed: expected {expected}, N, K, G >= 1")
    if kind == "episode":
        return (1, "episode"), n
    return (n, "step"), steps


@dataclass(frozen=True)
class TrainingSetup:
    """One value per factor (see the module docstring)."""

    vehicle: str = "uuv_simulator"
    control_period: float = 0.2
    updates: str = "episode:10"
    prior_updates: str = ""
    oa_updates: str = ""
    oa_gamma: float | None = None
    pf_sine_gamma: float | None = None
    spnn_gamma: float | None = None
    pnn_gamma: float | None = None
    pnn_gamma_sine: float | None = None
    batch_size: int = PAPER_BATCH_SIZE
    prior_batch_size: int = 0
    train_start_noise: bool = False
    pf_start_spread: float | None = None
    planning_start_spread: float | None = None
    learner_sonar_noise: float = 0.0
    motion_obs: bool = False
    success_reward: float = 0.0
    progress_weighted: bool = False
    progress_along: str = "path"
    planning_progress_along: str | None = None
    pf_progress_weighted: bool | None = None
    net_arch: tuple[int, ...] = (255, 255)
    pnn_net_arch: tuple[int, ...] = ()
    target_entropy_ratio: float = DEFAULT_TARGET_ENTROPY_RATIO
    learner_target_entropy_ratio: float | None = None
    keep_best: bool = False
    keep_best_drawn: int = 0
    keep_best_by: str = "return"
    spnn_keep_best_by_sine: str | None = None
    keep_best_route_bound: float | None = None
    keep_best_route_bound_sine: float | None = None
    keep_best_also: str = ""
    prior_keep_best_by: str = "return"
    prior_keep_best_by_pf_straight: str | None = None
    pnn_lateral_init: float = 1.0
    pnn_lateral_init_sine: float | None = None
    pnn_critic_priors: str = "both"
    pnn_start_as_prior: str = "neither"
    spnn_start_as_prior: bool = False
    pnn_init_from_prior: str = "neither"
    spnn_init_from_prior: str = "neither"
    pnn_avoidance_column: str = "neither"
    pnn_near_prior_kl: str = "neither"
    spnn_d_th: float = PAPER_D_TH
    spnn_d_th_sine: float | None = None
    spnn_gate: str = "hard"
    spnn_gate_sine: str | None = None
    spnn_gate_temperature: float = 2.0
    spnn_gate_corridor: float | None = None
    spnn_switch_memory: float | None = None
    spnn_play_memory: float | None = None
    spnn_play_no_reversal: str = "neither"
    pnn_play_no_reversal: str = "neither"
    learners_play_no_reversal: str = "neither"
    spnn_sigma: float = PAPER_SIGMA
    spnn_own_weight: float = PAPER_OWN_WEIGHT
    spnn_prior_kl: float = 0.0
    pnn_prior_kl: float = 0.0
    pnn_prior_kl_clearance: float | None = None
    spnn_off_path_kl: float = 0.0
    spnn_off_path_kl_sine: float | None = None
    pnn_off_path_kl: float = 0.0
    pnn_off_path_kl_sine: float | None = None
    pnn_clear_kl: float = 0.0
    pnn_clear_kl_sine: float | None = None
    spnn_clear_kl: float = 0.0
    spnn_clear_kl_sine: float | None = None
    pnn_obstacle_kl: float = 0.0
    pnn_obstacle_kl_sine: float | None = None
    spnn_obstacle_kl: float = 0.0
    spnn_obstacle_kl_sine: float | None = None
    pnn_near_corridor: float | None = None
    pnn_near_corridor_sine: float | None = None
    spnn_n_steps: int = 1
    pnn_n_steps: int = 1
    pnn_n_steps_sine: int | None = None
    pf_n_steps: int = 1
    pf_validation_every: int = VALIDATION_EVERY
    spnn_action_smoothness: float = 0.0
    pnn_action_smoothness: float = 0.0
    exploration_epsilon: float = 0.0
    pnn_exploration_epsilon: float | None = None
    pnn_exploration_epsilon_sine: float | None = None
    mirror_augmentation: bool = False
    oa_mirror: bool = False
    goal_obs: bool = False
    pnn_goal_obs: bool = True
    goal_distance: float | None = None
    heading_rule: str = "path"
    oa_layout: str = "avoidance"
    oa_corridor: float | None = None
    oa_time_limit: float | None = None
    oa_budget: float = 1.0
    pf_sine_budget: float = 1.0
    oa_offset_obs: bool = False
    prior_candidates: int = 1
    prior_candidates_pf_straight: int | None = None
    prior_retries: int = 0
    planning_layout: str = "fixed"
    planning_obstacle_penalty: float = 1.0
    planning_arrival_gate: float = 0.0
    pf_arrival_gate: float = 0.0
    sonar_span: float = 180.0
    sonar_sectors: int = 9
    los_lookahead: float = DEFAULT_LOOKAHEAD

    def __post_init__(self) -> None:
        if self.vehicle not in VEHICLES:
            raise ValueError(
                f"vehicle={self.vehicle!r} is not allowed: expected one of {list(VEHICLES)}"
            )
        parse_updates(self.updates)
        for name in ("prior_updates", "oa_updates"):
            if getattr(self, name):
                parse_updates(getattr(self, name), name)
        for name, low in (
            ("batch_size", 1),
            ("prior_batch_size", 0),
            ("prior_candidates", 1),
            ("prior_retries", 0),
            ("keep_best_drawn", 0),
            ("spnn_n_steps", 1),
            ("pnn_n_steps", 1),
            ("pf_n_steps", 1),
            ("pf_validation_every", 1),
            ("sonar_sectors", 1),
        ):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < low:
                raise ValueError(
                    f"{name}={value!r} is not allowed: expected an integer >= {low}"
                    + (" (0: as batch_size)" if name == "prior_batch_size" else "")
                )
        for name in ("oa_gamma", "pf_sine_gamma", "spnn_gamma", "pnn_gamma", "pnn_gamma_sine"):
            gamma = getattr(self, name)
            if gamma is not None and not (is_finite_number(gamma) and 0.0 < gamma < 1.0):
                fallback = (
                    "pnn_gamma's" if name == "pnn_gamma_sine" else f"Tables 2-3's {PAPER_GAMMA}"
                )
                raise ValueError(
                    f"{name}={gamma!r} is not allowed: expected a discount factor in (0, 1), "
                    f"or None for {fallback}"
                )
        for name, refined in (
            ("pnn_n_steps_sine", "pnn_n_steps"),
            ("prior_candidates_pf_straight", "prior_candidates"),
        ):
            value = getattr(self, name)
            if value is not None and (
                isinstance(value, bool) or not isinstance(value, int) or value < 1
            ):
                raise ValueError(
                    f"{name}={value!r} is not allowed: expected an integer >= 1, or None "
                    f"for {refined}'s value"
                )
        if self.prior_retries and not self.keep_best:
            raise ValueError(
                f"prior_retries={self.prior_retries} is not allowed with keep_best off: a column "
                "is trained again when none of its validation checks passes (keep_best=true)"
            )
        for name in ("prior_candidates", "prior_candidates_pf_straight"):
            value = getattr(self, name)
            if value is not None and value > 1 and not self.keep_best:
                raise ValueError(
                    f"{name}={value} is not allowed with keep_best off: the best candidate is "
                    "chosen on its validation checks (keep_best=true)"
                )
        optional = {
            "prior_keep_best_by_pf_straight": "prior_keep_best_by's",
            "spnn_keep_best_by_sine": "keep_best_by's",
        }
        for name in ("keep_best_by", "prior_keep_best_by", *optional):
            value = getattr(self, name)
            if value is None and name in optional:
                continue
            if value not in RANKINGS:
                raise ValueError(
                    f"{name}={value!r} is not allowed: expected one of {list(RANKINGS)}"
                    + (f" (or None for {optional[name]})" if name in optional else "")
                )
            # without checks SPNN's sine runs keep their last policy, as "last" does
            if value != "return" and not self.keep_best and name != "spnn_keep_best_by_sine":
                raise ValueError(
                    f"{name}={value!r} is not allowed with keep_best off: it ranks the "
                    "validation checks (keep_best=true)"
                )
        also = self.learner_keep_best_also()
        if also and not self.keep_best:
            raise ValueError(
                f"keep_best_also={self.keep_best_also!r} is not allowed with keep_best off: it "
                "ranks the validation checks (keep_best=true)"
            )
        for name, meaning in (
            ("keep_best_route_bound", "no bound"),
            ("keep_best_route_bound_sine", "keep_best_route_bound's"),
        ):
            bound = getattr(self, name)
            if bound is not None and not (is_finite_number(bound) and bound > 0):
                raise ValueError(
                    f"{name}={bound!r} is not allowed: expected a mean abs(g) in metres > 0, "
                    f"or None for {meaning}"
                )
        if self.keep_best_drawn and not self.keep_best:
            raise ValueError(
                f"keep_best_drawn={self.keep_best_drawn} is not allowed with keep_best off: "
                "the drawn-obstacle episodes rank the validation checks (keep_best=true)"
            )
        _check_refined_numbers(
            self,
            ("target_entropy_ratio", "learner_target_entropy_ratio"),
            lambda value: 0.0 < value <= 1.0,
            "a number in (0, 1]",
        )
        _check_refined_numbers(
            self,
            ("exploration_epsilon", "pnn_exploration_epsilon", "pnn_exploration_epsilon_sine"),
            lambda value: 0.0 <= value < 1.0,
            "a probability in [0, 1)",
        )
        _check_refined_numbers(
            self,
            ("spnn_off_path_kl", "spnn_off_path_kl_sine"),
            lambda value: value >= 0.0,
            "a finite weight >= 0",
        )
        _check_refined_numbers(
            self,
            ("pnn_off_path_kl", "pnn_off_path_kl_sine"),
            lambda value: value >= 0.0,
            "a finite weight >= 0",
        )
        for names in (
            ("pnn_clear_kl", "pnn_clear_kl_sine"),
            ("spnn_clear_kl", "spnn_clear_kl_sine"),
            ("pnn_obstacle_kl", "pnn_obstacle_kl_sine"),
            ("spnn_obstacle_kl", "spnn_obstacle_kl_sine"),
        ):
            _check_refined_numbers(self, names, lambda value: value >= 0.0, "a finite weight >= 0")
        for name, before in (
            ("pnn_near_corridor", "spnn_gate_corridor"),
            ("pnn_near_corridor_sine", "pnn_near_corridor"),
        ):
            value = getattr(self, name)
            if value is not None and not (is_finite_number(value) and 0 < value <= 1):
                raise ValueError(
                    f"{name}={value!r} is not allowed: expected a fraction of d_L in (0, 1], "
                    f"or None for {before}'s value"
                )
        if not (is_finite_number(self.sonar_span) and 0.0 < self.sonar_span <= 360.0):
            raise ValueError(
                f"sonar_span={self.sonar_span!r} is not allowed: expected an angle in (0, 360] "
                "(degrees)"
            )
        low, high = LOOKAHEAD_RANGE  # the tasks' own range, checked here before float() below
        if not (is_finite_number(self.los_lookahead) and low <= self.los_lookahead <= high):
            raise ValueError(
                f"los_lookahead={self.los_lookahead!r} is not allowed: expected a distance in "
                f"[{low:g}, {high:g}] (m)"
            )
        for name in ("spnn_d_th", "spnn_d_th_sine"):
            value = getattr(self, name)
            if name == "spnn_d_th_sine" and value is None:
                continue
            if not (is_finite_number(value) and value > 0.0):
                raise ValueError(
                    f"{name}={value!r} is not allowed: expected a distance > 0 (m)"
                    + (", or None for spnn_d_th's" if name == "spnn_d_th_sine" else "")
                )
        from sb3_pnn.progressive.gates import GATES

        for name in ("spnn_gate", "spnn_gate_sine"):
            value = getattr(self, name)
            if value not in GATES and not (name == "spnn_gate_sine" and value is None):
                raise ValueError(
                    f"{name}={value!r} is not allowed: expected one of {list(GATES)}"
                    + (" (or None for spnn_gate's)" if name == "spnn_gate_sine" else "")
                )
        corridor = self.spnn_gate_corridor
        if corridor is not None:
            if not (is_finite_number(corridor) and 0 < corridor <= 1):
                raise ValueError(
                    f"spnn_gate_corridor={corridor!r} is not allowed: expected a fraction of "
                    "d_L in (0, 1], or None"
                )
            if "learned" in (self.spnn_gate, self.spnn_gate_sine):
                raise ValueError(
                    f"spnn_gate_corridor={corridor!r} is not allowed with a learned gate: it "
                    "bounds the distance gates ('hard', 'soft'); add spnn_gate_corridor=null"
                )
        memory = self.spnn_switch_memory
        if memory is not None and not (is_finite_number(memory) and 0 <= memory <= 100):
            raise ValueError(
                f"spnn_switch_memory={memory!r} is not allowed: expected a distance in [0, 100] "
                "(m), or None for eq. 15's switch without memory"
            )
        memory = self.spnn_play_memory
        if memory is not None and not (is_finite_number(memory) and 0 < memory <= 100):
            raise ValueError(
                f"spnn_play_memory={memory!r} is not allowed: expected a distance in (0, 100] "
                "(m), or None to evaluate SPNN with eq. 15's switch as trained"
            )
        if memory is not None and self.spnn_switch_memory is not None:
            raise ValueError(
                f"spnn_play_memory={memory!r} is not allowed with spnn_switch_memory="
                f"{self.spnn_switch_memory!r}: a run trained with the latch part already plays "
                "with its memory; set one of them to null"
            )
        temperature = self.spnn_gate_temperature
        if not (is_finite_number(temperature) and temperature > 0):
            raise ValueError(
                f"spnn_gate_temperature={temperature!r} is not allowed: expected a distance > 0 (m)"
            )
        for name in (
            "spnn_sigma",
            "spnn_own_weight",
            "spnn_prior_kl",
            "pnn_prior_kl",
            "spnn_action_smoothness",
            "pnn_action_smoothness",
        ):
            value = getattr(self, name)
            if not is_finite_number(value) or value < 0:
                raise ValueError(f"{name}={value!r} is not allowed: expected a finite weight >= 0")
        for name in PER_PATH_FACTORS:
            value = getattr(self, name)
            if isinstance(value, bool):  # --set pnn_critic_priors=true / false
                object.__setattr__(self, name, "both" if value else "neither")
            if getattr(self, name) not in PATH_CHOICES:
                raise ValueError(
                    f"{name}={value!r} is not allowed: expected one of "
                    f"{list(PATH_CHOICES)} (or true / false)"
                )
        for name in ("pf_start_spread", "planning_start_spread"):
            spread = getattr(self, name)
            if spread is not None and not (is_finite_number(spread) and 0 <= spread <= 30):
                raise ValueError(
                    f"{name}={spread!r} is not allowed: expected a number in [0, 30] (a "
                    "multiple of 1 m and 5 deg), or None for train_start_noise's value"
                )
        from rov_envs.sim.config import SONAR_RANGE

        noise = self.learner_sonar_noise
        if not (is_finite_number(noise) and 0 <= noise <= SONAR_RANGE):
            raise ValueError(
                f"learner_sonar_noise={noise!r} is not allowed: expected a std in "
                f"[0, {SONAR_RANGE:g}] (m, at most the sonar's range)"
            )
        clearance = self.pnn_prior_kl_clearance
        if clearance is not None and not (is_finite_number(clearance) and clearance > 0):
            raise ValueError(
                f"pnn_prior_kl_clearance={clearance!r} is not allowed: expected a distance > 0 "
                "(m), or None for every sample"
            )
        sine_init = self.pnn_lateral_init_sine
        if sine_init is not None and not is_finite_number(sine_init):
            raise ValueError(
                f"pnn_lateral_init_sine={sine_init!r} is not allowed: expected a number, or None "
                "for pnn_lateral_init's value"
            )
        for name, empty in (("net_arch", ""), ("pnn_net_arch", ", or [] for net_arch's")):
            widths = getattr(self, name)
            if (not widths and not empty) or any(int(w) < 1 for w in widths):
                raise ValueError(f"{name}={widths!r} is not allowed: expected widths >= 1{empty}")
            object.__setattr__(self, name, tuple(int(w) for w in widths))
        from rov_envs.sim.layouts import LAYOUT_CODES

        if self.oa_layout not in LAYOUT_CODES:
            raise ValueError(
                f"oa_layout={self.oa_layout!r} is not allowed: expected one of "
                f"{sorted(LAYOUT_CODES)}"
            )
        corridor = self.oa_corridor
        if corridor is not None and not (is_finite_number(corridor) and 1 <= corridor <= 100):
            raise ValueError(
                f"oa_corridor={corridor!r} is not allowed: expected a half-width in [1, 100] (m), "
                "or None for the task's own"
            )
        limit = self.oa_time_limit
        if limit is not None and not (is_finite_number(limit) and 10 <= limit <= 1000):
            raise ValueError(
                f"oa_time_limit={limit!r} is not allowed: expected simulated seconds in "
                "[10, 1000], or None for the task's own (120 s)"
            )
        for name, column in (("oa_budget", "avoidance-column"), ("pf_sine_budget", "sine column")):
            multiple = getattr(self, name)
            if not (is_finite_number(multiple) and 0 < multiple <= 20):
                raise ValueError(
                    f"{name}={multiple!r} is not allowed: expected a multiple in (0, 20] of the "
                    f"budget's {column} episodes"
                )
        penalty = self.planning_obstacle_penalty
        if isinstance(penalty, bool) or not is_finite_number(penalty) or penalty < 0:
            raise ValueError(
                f"planning_obstacle_penalty={penalty!r} is not allowed: expected a finite number "
                ">= 0 (1: eq. 20 as the paper weights it)"
            )
        for name in ("planning_arrival_gate", "pf_arrival_gate"):
            gate = getattr(self, name)
            if (
                isinstance(gate, bool)
                or not is_finite_number(gate)
                or not (gate == 0 or 2 <= gate <= 100)
            ):
                raise ValueError(
                    f"{name}={gate!r} is not allowed: expected 0 (none) or metres in [2, 100] "
                    "from the target point"
                )
        if self.planning_layout not in ("fixed", "scatter"):
            raise ValueError(
                f"planning_layout={self.planning_layout!r} is not allowed: expected 'fixed' "
                "(the paper's obstacles) or 'scatter' (drawn afresh each training episode)"
            )
        if self.heading_rule not in ("path", "goal"):
            raise ValueError(
                f"heading_rule={self.heading_rule!r} is not allowed: expected 'path' or 'goal'"
            )
        for name, along in (
            ("progress_along", self.progress_along),
            ("planning_progress_along", self.planning_progress_along),
        ):
            if along not in PROGRESS_DIRECTIONS and not (
                name.startswith("planning") and along is None
            ):
                raise ValueError(
                    f"{name}={along!r} is not allowed: expected 'path' (the path's tangent) or "
                    "'course' (the LOS course)"
                    + (", or None (progress_along's)" if name.startswith("planning") else "")
                )
        self._check_env_kwargs()

    def _check_env_kwargs(self) -> None:
        """Every task must accept the set-up's env keywords (a bad control period, say, is
        refused here, before any run starts, not by every run of a study)."""
        from rov_envs.sim.config import make_config
        from rov_envs.sim.tasks import TASKS

        for task in TASKS:
            make_config(task, **self.train_env_kwargs())

    def env_kwargs(self) -> dict[str, Any]:
        """Environment keyword arguments shared by training and evaluation (one set for every
        task: the goal factors name a departure from the tasks' own defaults, which differ
        by task, see :mod:`rov_envs.sim.tasks`)."""
        kwargs: dict[str, Any] = {
            "vehicle": self.vehicle,
            "control_period": float(self.control_period),
            "motion_obs": bool(self.motion_obs),
            "success_reward": float(self.success_reward),
            "progress_weighted": bool(self.progress_weighted),
            "goal_distance": None if self.goal_distance is None else float(self.goal_distance),
        }
        if not self.goal_obs:  # every task observes "path" (and its sonar): the paper's state
            kwargs.update(goal_obs=False, path_obs=True)
        if self.progress_along != "path":  # named only off the tangent, so runs keep their hash
            kwargs["progress_along"] = self.progress_along
        if self.heading_rule != "goal":  # eq. 21 as written: a_c of the path (the LOS course)
            kwargs["heading_rule"] = self.heading_rule
        from rov_envs.sim.config import SONAR_SECTORS, SONAR_SPAN

        span = math.radians(self.sonar_span)
        if not math.isclose(span, SONAR_SPAN) or self.sonar_sectors != SONAR_SECTORS:
            # named only off the tasks' own sonar, so earlier runs keep their hash
            kwargs.update(sonar_span=span, sonar_sectors=self.sonar_sectors)
        if self.los_lookahead != DEFAULT_LOOKAHEAD:  # named only off rov_envs' 5 m (hashes)
            kwargs["los_lookahead"] = float(self.los_lookahead)
        return kwargs

    def agent_env_kwargs(self, agent: str, path: str = "") -> dict[str, Any]:
        """What one learner's planning runs on ``path`` add to :meth:`env_kwargs` (training and
        evaluation alike): PNN without the "goal" part when ``pnn_goal_obs`` is off, its only
        prior being a path follower that reads the path part (the part is there for SPNN's
        avoidance column); SPNN's ``obstacle_latch`` where ``spnn_switch_memory`` acts; every
        learner's ``planning_obstacle_penalty`` when it is not the paper's, its
        ``planning_progress_along`` when it differs from the source columns', and
        :meth:`ending_env_kwargs`."""
        kwargs: dict[str, Any] = {}
        latch = self.spnn_latch_of(path) if agent == "spnn" else None
        if latch is not None:  # named only when on, so earlier runs keep their hash
            kwargs["obstacle_latch"] = list(latch)
        if self.planning_obstacle_penalty != 1.0:  # named only off the paper's weight (hashes)
            kwargs["obstacle_penalty"] = float(self.planning_obstacle_penalty)
        kwargs.update(self.ending_env_kwargs())
        along = self.planning_progress_along
        if along is not None and along != self.progress_along:  # named only when it differs
            kwargs["progress_along"] = along
        if agent == "pnn" and self.goal_obs and not self.pnn_goal_obs:
            kwargs["goal_obs"] = False
        reads_avoidance = agent == "spnn" or (agent == "pnn" and self.pnn_reads_avoidance(path))
        if reads_avoidance and self.oa_offset_obs:  # the avoidance column reads what it trained on
            kwargs["goal_offset"] = True
        return kwargs

    def ending_env_kwargs(self) -> dict[str, Any]:
        """How the planning tasks end, for the learners and the baselines alike: the
        ``planning_arrival_gate`` when there is one (named only then, so runs keep their hash)."""
        gate = self.planning_arrival_gate
        return {"arrival_gate": float(gate)} if gate else {}

    def source_env_kwargs(self, env_id: str) -> dict[str, Any]:
        """What a source column's task adds to :meth:`env_kwargs` (training and evaluation
        alike): the obstacle-avoidance column's offset from its route (``oa_offset_obs``), the
        path-following columns' ``pf_progress_weighted`` where it differs and their
        ``pf_arrival_gate``."""
        from rov_envs.sim.tasks import task_of_env

        task = task_of_env(env_id).name
        if self.oa_offset_obs and task == "ObstacleAvoidance":
            return {"goal_offset": True}
        if not task.startswith("PathFollowing"):
            return {}
        kwargs: dict[str, Any] = {}
        weighted = self.pf_progress_weighted
        if weighted is not None and weighted != self.progress_weighted:
            kwargs["progress_weighted"] = bool(weighted)  # named only when it differs (hashes)
        if self.pf_arrival_gate:  # named only when set (hashes)
            kwargs["arrival_gate"] = float(self.pf_arrival_gate)
        return kwargs

    def train_env_kwargs(self, env_id: str | None = None) -> dict[str, Any]:
        """Keyword arguments of the training environment (start noise and the learners' sonar
        noise included, :data:`TRAINING_ONLY_ENV_KWARGS`); for
        ``env_id``'s task also the obstacles it trains on (``oa_layout`` for the
        obstacle-avoidance task, ``planning_layout`` for the planning tasks), when they are not
        the task's own."""
        noise = TRAIN_START_NOISE if self.train_start_noise else (0.0, 0.0)
        spread = self._start_spread(env_id)
        if self.train_start_noise and spread is not None:
            noise = tuple(float(spread) * n for n in TRAIN_START_NOISE)
        kwargs = {**self.env_kwargs(), "start_noise": list(noise)}
        layout = self._training_layout(env_id) if env_id is not None else None
        if layout is not None:
            kwargs["layout"] = layout
        if env_id is not None:
            from rov_envs.sim.tasks import task_of_env

            kwargs.update(self.source_env_kwargs(env_id))
            task = task_of_env(env_id).name
            if self.learner_sonar_noise and task.startswith("Planning"):  # the learners' tasks
                kwargs["sonar_noise"] = float(self.learner_sonar_noise)
            if task == "ObstacleAvoidance":
                if self.oa_corridor is not None:
                    kwargs["corridor"] = float(self.oa_corridor)
                if self.oa_time_limit is not None:
                    kwargs["max_episode_seconds"] = float(self.oa_time_limit)
        return kwargs

    def _start_spread(self, env_id: str | None) -> float | None:
        """The multiple of the training start noise that ``env_id``'s task trains from
        (``pf_start_spread`` on the path-following tasks, ``planning_start_spread`` on the
        planning tasks), None for 1x."""
        if env_id is None:
            return None
        from rov_envs.sim.tasks import task_of_env

        name = task_of_env(env_id).name
        if name.startswith("PathFollowing"):
            return self.pf_start_spread
        if name.startswith("Planning"):
            return self.planning_start_spread
        return None

    def _training_layout(self, env_id: str) -> str | None:
        """The layout ``env_id``'s training episodes draw, None for the task's own."""
        from rov_envs.sim.tasks import task_of_env

        task = task_of_env(env_id)
        if task.name == "ObstacleAvoidance" and self.oa_layout != task.layout:
            return self.oa_layout
        if task.name.startswith("Planning") and self.planning_layout != "fixed":
            return self.planning_layout
        return None

    def on_path(self, name: str, path: str) -> bool:
        """Whether the per-path factor ``name`` is on for planning path ``path``."""
        if path not in PATH_CHOICES["both"]:
            raise ValueError(f"path={path!r} is not allowed: expected 'straight' or 'sine'")
        return path in PATH_CHOICES[getattr(self, name)]

    def sac_kwargs(
        self, prior: bool = False, agent: str = "", path: str = "", column: str = ""
    ) -> dict[str, Any]:
        """DiscreteSAC keyword arguments (the rest are the paper's Tables 2-3 defaults); with
        ``prior``, those of a source column's run (``prior_updates``, ``prior_batch_size``; for
        ``column="oa"``, the avoidance column, ``oa_updates`` and ``oa_gamma`` where set; for the
        path-following columns ``pf_straight`` / ``pf_sine``, ``pf_n_steps``, and for
        ``pf_sine`` ``pf_sine_gamma``);
        ``agent="pnn"`` adds PNN's ``lateral_scale_init``, ``pnn_gamma`` and, on planning path
        ``path`` (``"straight"`` or ``"sine"``), ``critic_priors`` and ``start_as_prior``;
        ``agent="spnn"`` SPNN's ``d_th``, ``sigma``, ``own_weight``, ``start_as_prior`` and
        ``spnn_gamma``."""
        updates = self.prior_updates if prior and self.prior_updates else self.updates
        if prior and column == "oa" and self.oa_updates:
            updates = self.oa_updates
        train_freq, gradient_steps = parse_updates(updates)
        kwargs: dict[str, Any] = {
            "learning_starts": LEARNING_STARTS,
            "train_freq": list(train_freq),
            "gradient_steps": gradient_steps,
            "policy_kwargs": {"net_arch": list(self.net_arch)},
        }
        if agent == "pnn" and not prior and self.pnn_net_arch:  # named only when set (hashes)
            kwargs["policy_kwargs"]["net_arch"] = list(self.pnn_net_arch)
        gamma = {"oa": self.oa_gamma, "pf_sine": self.pf_sine_gamma}.get(column) if prior else None
        if not prior and agent in ("spnn", "pnn"):
            gamma = self.spnn_gamma if agent == "spnn" else self.pnn_gamma_of(path)
        if gamma is not None and gamma != PAPER_GAMMA:  # named only off Table 2's (hashes)
            kwargs["gamma"] = float(gamma)
        batch_size = self.prior_batch_size if prior and self.prior_batch_size else self.batch_size
        # Named only when it departs from DiscreteSAC's default, so that the specs (and result
        # hashes) of runs made before this factor existed stay the same.
        entropy_ratio = self.target_entropy_ratio_of(agent if not prior else "")
        if entropy_ratio != DEFAULT_TARGET_ENTROPY_RATIO:
            kwargs["target_entropy_ratio"] = entropy_ratio
        if batch_size != PAPER_BATCH_SIZE:
            kwargs["batch_size"] = batch_size
        for name, (reader, key) in AGENT_FACTORS.items():  # written always: the policies'
            if agent == reader:  # own defaults are the recommended set-up's, not the paper's
                kwargs["policy_kwargs"][key] = self._policy_value(name, path)[0]
        clearance = self.pnn_prior_kl_clearance
        if agent == "pnn" and clearance is not None and self.pnn_prior_kl > 0:
            # named only when it acts, so runs without the term keep their hash
            kwargs["policy_kwargs"]["prior_kl_clearance"] = float(clearance)
        smoothness = {"spnn": self.spnn_action_smoothness, "pnn": self.pnn_action_smoothness}
        if smoothness.get(agent, 0.0) > 0:  # named only when on, so earlier runs keep their hash
            kwargs["policy_kwargs"]["action_smoothness"] = float(smoothness[agent])
        # the learners' runs only, named only when on (so earlier runs keep their hash)
        epsilon = self.exploration_epsilon_of(agent, path) if agent and not prior else 0.0
        if epsilon > 0:
            kwargs["exploration_epsilon"] = epsilon
        mirrored = self.oa_mirror if prior else self.mirror_augmentation and bool(agent)
        if mirrored and (column == "oa" or not prior):  # named only when on, as epsilon
            kwargs["mirror"] = copy.deepcopy(LEFT_RIGHT_MIRROR)
        n_steps = {"spnn": self.spnn_n_steps}.get(agent, 1)
        n_steps = self.pnn_n_steps_of(path) if agent == "pnn" else n_steps
        if prior and column.startswith("pf_"):
            n_steps = self.pf_n_steps
        if n_steps != 1:  # named only off one-step targets, so earlier runs keep their hash
            kwargs["n_steps"] = n_steps
        gate = self.spnn_gate_of(path) if agent == "spnn" else "hard"
        if gate != "hard":  # named only off the paper's switch, so earlier runs keep their hash
            kwargs["policy_kwargs"]["gate"] = gate
            if gate == "soft":
                kwargs["policy_kwargs"]["temperature"] = float(self.spnn_gate_temperature)
        for term in ("off_path_kl", "clear_kl", "obstacle_kl"):  # KL over copies of each batch
            weight = self.copy_kl_of(agent, term, path)
            if weight > 0:  # named only when on, so earlier runs keep their hash
                kwargs["policy_kwargs"][term] = weight
                if term == "obstacle_kl":  # the sonar span that places the drawn obstacles
                    kwargs["policy_kwargs"]["obstacle_kl_span"] = math.radians(self.sonar_span)
        if agent == "spnn" and self.spnn_gate_corridor is not None:  # named only when set
            kwargs["policy_kwargs"]["gate_corridor"] = float(self.spnn_gate_corridor)
        if agent == "spnn" and self.spnn_latch_of(path) is not None:  # named only when on
            kwargs["policy_kwargs"]["gate_latch_key"] = "latch"
        if agent == "pnn" and self.pnn_reads_avoidance(path):  # named only when on
            kwargs["policy_kwargs"]["reference_prior"] = 0
            if self.pnn_near_prior_kl_on(path):  # named only when it acts
                kwargs["policy_kwargs"]["near_reference_prior"] = 1
                corridor = self.pnn_near_corridor_of(path)
                if corridor is not None:
                    kwargs["policy_kwargs"]["near_reference_corridor"] = float(corridor)
        return kwargs

    def pnn_near_corridor_of(self, path: str) -> float | None:
        """The corridor bound of PNN's near reference on planning path ``path``: beyond this
        fraction of d_L the path-following column stays the KL term's reference near obstacles
        (``pnn_near_corridor_sine`` on the sine path when set, else ``pnn_near_corridor``, else
        SPNN's ``spnn_gate_corridor``)."""
        own = self.pnn_near_corridor
        corridor = self.spnn_gate_corridor if own is None else own
        return self._on_sine_path("pnn_near_corridor_sine", corridor, path)

    def pnn_near_prior_kl_on(self, path: str) -> bool:
        """Whether PNN's KL term on planning path ``path`` pulls toward the avoidance column
        near obstacles: ``pnn_near_prior_kl`` on that path, where PNN reads the column and its
        KL term has a clearance (elsewhere the factor does nothing)."""
        return (
            self.on_path("pnn_near_prior_kl", path)
            and self.pnn_reads_avoidance(path)
            and self.pnn_prior_kl > 0
            and self.pnn_prior_kl_clearance is not None
        )

    def pnn_reads_avoidance(self, path: str) -> bool:
        """Whether PNN's runs on planning path ``path`` read the avoidance column beside the
        path-following one (``pnn_avoidance_column``), with the latter as their reference."""
        return self.pnn_avoidance_column != "neither" and self.on_path("pnn_avoidance_column", path)

    def spnn_latch_of(self, path: str) -> tuple[float, float] | None:
        """The ``obstacle_latch`` (on, off) in metres of SPNN's runs on planning path ``path``:
        (d_th, d_th + ``spnn_switch_memory``) where that is set and the path's gate is the hard
        switch, else None."""
        if self.spnn_switch_memory is None:
            return None
        if path not in ("straight", "sine"):
            raise ValueError(
                f"spnn_switch_memory={self.spnn_switch_memory!r} depends on the path: expected "
                "path='straight' or 'sine'"
            )
        if self.spnn_gate_of(path) != "hard":
            return None
        d_th = float(self._policy_value("spnn_d_th", path)[0])
        return (d_th, d_th + float(self.spnn_switch_memory))

    def spnn_play_memory_of(self, path: str) -> float | None:
        """The hysteresis H (m) with which the study evaluates SPNN's runs on planning path
        ``path`` through :class:`sb3_pnn.progressive.SwitchMemory`: ``spnn_play_memory`` where
        the path's gate is eq. 15's hard switch, else None (evaluated as trained)."""
        if self.spnn_play_memory is None or self.spnn_gate_of(path) != "hard":
            return None
        return float(self.spnn_play_memory)

    def target_entropy_ratio_of(self, agent: str) -> float:
        """The target entropy's fraction of log|A| for a run of learner ``agent`` (``""``: a
        source column): ``learner_target_entropy_ratio`` for the learners where set, else
        ``target_entropy_ratio``."""
        own = self.learner_target_entropy_ratio
        return float(self.target_entropy_ratio if not agent or own is None else own)

    def exploration_epsilon_of(self, agent: str, path: str) -> float:
        """The learner ``agent``'s exploration epsilon on planning path ``path``: PNN's runs read
        ``pnn_exploration_epsilon`` (and ``pnn_exploration_epsilon_sine`` on the sine path) where
        set, every learner else ``exploration_epsilon``."""
        if agent != "pnn":
            return float(self.exploration_epsilon)
        own = self.pnn_exploration_epsilon
        epsilon = self.exploration_epsilon if own is None else own
        return float(self._on_sine_path("pnn_exploration_epsilon_sine", epsilon, path))

    def pnn_n_steps_of(self, path: str) -> int:
        """PNN's return length n on planning path ``path`` (``pnn_n_steps_sine`` on the sine
        path when set, else ``pnn_n_steps``)."""
        return self._on_sine_path("pnn_n_steps_sine", self.pnn_n_steps, path)

    def pnn_gamma_of(self, path: str) -> float | None:
        """PNN's discount on planning path ``path`` (``pnn_gamma_sine`` on the sine path when
        set, else ``pnn_gamma``; None: Tables 2-3's 0.99)."""
        return self._on_sine_path("pnn_gamma_sine", self.pnn_gamma, path)

    def copy_kl_of(self, agent: str, term: str, path: str) -> float:
        """The weight of learner ``agent``'s KL term ``term`` ("off_path_kl", "clear_kl" or
        "obstacle_kl", over off-path, clear-sonar or drawn-obstacle copies of each minibatch) on
        planning path ``path``: the factor
        ``<agent>_<term>``, refined on the sine path by ``<agent>_<term>_sine`` when set; 0 for
        an agent without such factors (SAC-Single, SAC-Multi)."""
        if agent not in ("spnn", "pnn"):
            return 0.0
        name = f"{agent}_{term}"
        return float(self._on_sine_path(f"{name}_sine", getattr(self, name), path))

    def spnn_gate_of(self, path: str) -> str:
        """The SPNN's gate on planning path ``path`` (``spnn_gate_sine`` on the sine path when
        set, else ``spnn_gate``)."""
        return self._on_sine_path("spnn_gate_sine", self.spnn_gate, path)

    def _on_sine_path(self, name: str, value: Any, path: str) -> Any:
        """``value`` on planning path ``path``, replaced on the sine path by the factor ``name``
        (one of :data:`SINE_PATH_FACTORS`) where that is set and differs; a differing
        refinement needs the path named."""
        sine = getattr(self, name)
        if sine is None or sine == value:
            return value
        if path not in ("straight", "sine"):
            raise ValueError(
                f"{name}={sine!r} depends on the path: expected path='straight' or 'sine'"
            )
        return sine if path == "sine" else value

    def _policy_value(self, name: str, path: str) -> tuple[Any, Any]:
        """(the policy keyword's value on planning path ``path``, its value in PAPER) for an
        agent factor; those in :data:`PER_PATH_FACTORS` are per path, the others the same on
        both paths, except ``pnn_lateral_init`` and ``spnn_d_th``, which
        ``pnn_lateral_init_sine`` and ``spnn_d_th_sine`` (when set) replace on the sine path."""
        if name == "pnn_lateral_init" and self.pnn_lateral_init_sine is not None:
            if not path:
                raise ValueError(
                    f"pnn_lateral_init_sine={self.pnn_lateral_init_sine!r} depends on the path: "
                    "expected path='straight' or 'sine'"
                )
            value = self.pnn_lateral_init_sine if path == "sine" else self.pnn_lateral_init
            return float(value), _FIELD_DEFAULTS[name]
        if name == "spnn_d_th":
            value = self._on_sine_path("spnn_d_th_sine", self.spnn_d_th, path)
            return float(value), _FIELD_DEFAULTS[name]
        if name not in PER_PATH_FACTORS:
            default = _FIELD_DEFAULTS[name]
            return type(default)(getattr(self, name)), default
        value, default = getattr(self, name), _FIELD_DEFAULTS[name] == "both"
        if value in ("both", "neither"):
            return value == "both", default
        if not path:
            raise ValueError(
                f"{name}={value!r} depends on the path: expected path='straight' or 'sine'"
            )
        return self.on_path(name, path), default

    def _for_column(self, name: str, column: str) -> Any:
        """Factor ``name``'s value for source column ``column``: its ``_pf_straight``
        refinement for the straight path-following column where that is set."""
        refined = getattr(self, f"{name}_pf_straight") if column == "pf_straight" else None
        return getattr(self, name) if refined is None else refined

    def column_episodes(self, column: str, budget_episodes: int) -> int:
        """Training episodes of source column ``column`` for a budget that gives it
        ``budget_episodes``: scaled by ``oa_budget`` for the avoidance column and by
        ``pf_sine_budget`` for the sine path-following column (at least 1)."""
        multiple = {"oa": self.oa_budget, "pf_sine": self.pf_sine_budget}.get(column, 1)
        if multiple == 1:
            return int(budget_episodes)
        return max(1, round(budget_episodes * multiple))

    def column_candidates(self, column: str) -> int:
        """How many training runs source column ``column`` (``pf_straight``, ``pf_sine`` or
        ``oa``) is the best of: ``prior_candidates``, or ``prior_candidates_pf_straight`` for
        the straight path-following column where that is set."""
        return int(self._for_column("prior_candidates", column))

    def column_keep_best_by(self, column: str) -> str:
        """What ranks the validation checks (and the candidates) of source column ``column``:
        ``prior_keep_best_by``, or ``prior_keep_best_by_pf_straight`` for the straight
        path-following column where that is set."""
        return str(self._for_column("prior_keep_best_by", column))

    def learner_keep_best_by(self, agent: str, path: str) -> str:
        """What ranks learner ``agent``'s checks on planning path ``path``:
        ``spnn_keep_best_by_sine`` for SPNN's sine runs where that is set, else ``keep_best_by``
        (also for an unnamed agent)."""
        if agent != "spnn":
            return self.keep_best_by
        return str(self._on_sine_path("spnn_keep_best_by_sine", self.keep_best_by, path))

    def validation(
        self, learner: bool = False, column: str = "", path: str = "", agent: str = ""
    ) -> dict[str, int | str]:
        """How often and on how many episodes a run validates (empty: it keeps the last policy);
        a learner's (``learner``) checks add ``keep_best_drawn`` episodes among drawn obstacles
        and rank by :meth:`learner_keep_best_by` of its ``agent`` within the route bound of its
        planning path ``path``
        (:meth:`route_bound_of`), source column ``column``'s by :meth:`column_keep_best_by`
        (named only when it is not the return, so that the specs of runs ranked by return keep
        their hash); a source column's add ``retries`` where ``prior_retries`` is not 0; the
        path-following columns check every ``pf_validation_every`` episodes."""
        if not self.keep_best:
            return {}
        every = self.pf_validation_every if column.startswith("pf_") else VALIDATION_EVERY
        checks: dict[str, int | str] = {"every": every, "episodes": VALIDATION_EPISODES}
        if learner and self.keep_best_drawn:
            checks["drawn_episodes"] = self.keep_best_drawn
        rank_by = (
            self.learner_keep_best_by(agent, path) if learner else self.column_keep_best_by(column)
        )
        if rank_by != "return":
            checks["rank_by"] = rank_by
        bound = self.route_bound_of(path) if learner else None
        if bound is not None:
            checks["route_bound"] = float(bound)
        if learner and self.keep_best_also:
            checks["also_rank_by"] = ",".join(self.learner_keep_best_also())
        if not learner and self.prior_retries:
            checks["retries"] = self.prior_retries
        return checks

    def learner_keep_best_also(self) -> tuple[str, ...]:
        """``keep_best_also`` as a tuple of rankings (empty: none); a name that is not one of
        :data:`RANKINGS` raises a ValueError naming it."""
        text = self.keep_best_also
        if not isinstance(text, str):
            raise ValueError(
                f"keep_best_also={text!r} is not allowed: expected comma-separated rankings "
                f"from {list(RANKINGS)}, e.g. 'route,last', or '' for none"
            )
        names = tuple(name.strip() for name in text.split(",") if name.strip())
        for name in names:
            if name not in RANKINGS:
                raise ValueError(
                    f"keep_best_also={text!r} is not allowed: {name!r} is not a ranking; "
                    f"expected comma-separated rankings from {list(RANKINGS)}, e.g. 'route,last'"
                )
        if len(set(names)) != len(names):
            raise ValueError(f"keep_best_also={text!r} is not allowed: a ranking named twice")
        return names

    def route_bound_of(self, path: str) -> float | None:
        """The learners' route bound on planning path ``path`` (``keep_best_route_bound_sine``
        on the sine path when set, else ``keep_best_route_bound``; None: no bound)."""
        return self._on_sine_path("keep_best_route_bound_sine", self.keep_best_route_bound, path)

    def to_dict(self) -> dict[str, Any]:
        data = asdict(self)
        data["net_arch"] = list(self.net_arch)
        return data

    def differences(self, other: TrainingSetup) -> dict[str, Any]:
        """Factors whose value differs from ``other``'s: name -> this set-up's value."""
        return {
            f.name: getattr(self, f.name)
            for f in fields(self)
            if getattr(self, f.name) != getattr(other, f.name)
        }

    def with_(self, **changes: Any) -> TrainingSetup:
        return replace(self, **changes)


#: The values of a per-path factor (``pnn_critic_priors``, ...): value -> the
#: planning paths on which it is on.
PATH_CHOICES: dict[str, tuple[str, ...]] = {
    "both": ("straight", "sine"),
    "straight": ("straight",),
    "sine": ("sine",),
    "neither": (),
}


def _check_refined_numbers(
    setup: TrainingSetup, names: Sequence[str], within: Callable[[float], bool], expected: str
) -> None:
    """Refuse a bad value of the number factor ``names[0]`` or of the factors that refine it in
    turn (``names[1:]``, each None for the value of the one before it): every value set must be
    a finite number for which ``within`` holds; the error names the factor, its value and
    ``expected``."""
    for index, name in enumerate(names):
        value = getattr(setup, name)
        if index and value is None:
            continue
        if not (is_finite_number(value) and within(value)):
            refines = f", or None for {names[index - 1]}'s value" if index else ""
            raise ValueError(f"{name}={value!r} is not allowed: expected {expected}{refines}")


#: Factors whose value names the planning paths they are on for.
PER_PATH_FACTORS: tuple[str, ...] = (
    "pnn_critic_priors",
    "pnn_start_as_prior",
    "pnn_init_from_prior",
    "spnn_init_from_prior",
    "pnn_avoidance_column",
    "pnn_near_prior_kl",
    "spnn_play_no_reversal",
    "pnn_play_no_reversal",
    "learners_play_no_reversal",
)

#: Factors that give the sine path its own value of another factor (None: that factor's).
SINE_PATH_FACTORS: tuple[str, ...] = (
    "pnn_lateral_init_sine",
    "spnn_gate_sine",
    "spnn_d_th_sine",
    "pnn_n_steps_sine",
    "pnn_exploration_epsilon_sine",
    "pnn_gamma_sine",
    "spnn_off_path_kl_sine",
    "pnn_off_path_kl_sine",
    "pnn_clear_kl_sine",
    "pnn_near_corridor_sine",
    "spnn_clear_kl_sine",
    "pnn_obstacle_kl_sine",
    "spnn_obstacle_kl_sine",
    "keep_best_route_bound_sine",
    "spnn_keep_best_by_sine",
)

#: Factors that one agent's policy reads: factor -> (agent, policy keyword argument), each
#: written into that agent's ``policy_kwargs``. (``pnn_lateral_init_sine`` reaches the PNN
#: through ``pnn_lateral_init``'s entry, :meth:`TrainingSetup._policy_value`.)
AGENT_FACTORS: dict[str, tuple[str, str]] = {
    "pnn_lateral_init": ("pnn", "lateral_scale_init"),
    "pnn_critic_priors": ("pnn", "critic_priors"),
    "pnn_start_as_prior": ("pnn", "start_as_prior"),
    "spnn_start_as_prior": ("spnn", "start_as_prior"),
    "pnn_init_from_prior": ("pnn", "init_from_prior"),
    "spnn_init_from_prior": ("spnn", "init_from_prior"),
    "spnn_d_th": ("spnn", "d_th"),
    "spnn_sigma": ("spnn", "sigma"),
    "spnn_own_weight": ("spnn", "own_weight"),
    "spnn_prior_kl": ("spnn", "prior_kl"),
    "pnn_prior_kl": ("pnn", "prior_kl"),
}
_FIELD_DEFAULTS: dict[str, Any] = {f.name: f.default for f in fields(TrainingSetup)}

#: The paper read literally: its vehicle, Table 3's update schedule, the exact start pose, the
#: state [a_c, g, d_1..d_q], eq. 17-21 without a success reward, Table 2's [255, 255] networks;
#: the control period it does not give is rov_envs' default.
PAPER = TrainingSetup()

#: The study's default set-up (each departure from PAPER is measured in docs/ablation/).
OURS = TrainingSetup(
    control_period=1.0,
    updates="step:2",
    prior_updates="step:1x2",
    train_start_noise=True,
    pf_start_spread=5.0,
    motion_obs=True,
    success_reward=200.0,
    progress_weighted=True,
    net_arch=(64, 64),
    keep_best=True,
    pnn_lateral_init=0.0,
    pnn_lateral_init_sine=1.0,
    pnn_critic_priors="straight",
    pnn_start_as_prior="straight",
    spnn_start_as_prior=True,
    spnn_sigma=1.0,
    spnn_own_weight=1.0,
    spnn_prior_kl=DEFAULT_PRIOR_KL,
    spnn_gate_sine="soft",
    spnn_keep_best_by_sine="last",
    spnn_gate_corridor=0.9,
    spnn_play_memory=10.0,
    spnn_play_no_reversal="sine",
    pnn_play_no_reversal="sine",
    spnn_off_path_kl_sine=1.0,
    spnn_clear_kl_sine=1.0,
    spnn_obstacle_kl_sine=0.5,
    pnn_prior_kl=1.0,
    pnn_prior_kl_clearance=PAPER_D_TH,
    pnn_avoidance_column="both",
    pnn_near_prior_kl="both",
    pnn_clear_kl=1.0,
    pnn_clear_kl_sine=0.0,
    pnn_near_corridor_sine=0.6,
    pnn_obstacle_kl_sine=0.5,
    pnn_n_steps=8,
    pnn_n_steps_sine=1,
    pnn_exploration_epsilon=0.05,
    pnn_exploration_epsilon_sine=0.0,
    goal_obs=True,
    goal_distance=25.0,
    heading_rule="goal",
    oa_layout="scatter",
    oa_budget=2.0,
    pf_sine_budget=2.0,
)

SETUPS: dict[str, TrainingSetup] = {"ours": OURS, "paper": PAPER}

#: Human-readable factor names (report tables).
FACTOR_LABELS: dict[str, str] = {
    "vehicle": "vehicle",
    "control_period": "control period (s)",
    "updates": "update schedule",
    "prior_updates": "update schedule of the source columns",
    "oa_updates": "update schedule of the avoidance column",
    "oa_gamma": "discount gamma of the avoidance column",
    "pf_sine_gamma": "discount gamma of the sine path-following column",
    "spnn_gamma": "discount gamma of SPNN's runs",
    "pnn_gamma": "discount gamma of PNN's runs",
    "pnn_gamma_sine": "discount gamma of PNN's runs on the sine path",
    "batch_size": "samples per update",
    "prior_batch_size": "samples per update of the source columns",
    "train_start_noise": "training start noise",
    "pf_start_spread": "path-following columns' training start noise (x 1 m, 5 deg)",
    "planning_start_spread": "learners' training start noise (x 1 m, 5 deg)",
    "learner_sonar_noise": "learners' training sonar noise std (m)",
    "motion_obs": "v, r observed",
    "success_reward": "success reward",
    "progress_weighted": "r_c weighted by progress",
    "progress_along": "progress of the weighted r_c measured along",
    "planning_progress_along": "learners' progress of the weighted r_c measured along",
    "pf_progress_weighted": "path-following columns' r_c weighted by progress",
    "net_arch": "hidden layers",
    "pnn_net_arch": "hidden layers of PNN's new column",
    "target_entropy_ratio": "target entropy / ln(number of actions)",
    "learner_target_entropy_ratio": "learners' target entropy / ln(number of actions)",
    "keep_best": "best policy on validation episodes kept",
    "keep_best_drawn": "learners' checks also among drawn obstacles (episodes)",
    "keep_best_by": "learners' checks of equal success ranked by",
    "spnn_keep_best_by_sine": "the same for SPNN's sine runs",
    "keep_best_route_bound": "learners' checks within this mean abs(g) (m) ranked first",
    "keep_best_route_bound_sine": "the same on the sine path",
    "keep_best_also": "learners' policies also kept by (model_by_<ranking>.zip)",
    "prior_keep_best_by": "source columns' checks of equal success ranked by",
    "pnn_lateral_init": "PNN lateral scale at the start",
    "pnn_lateral_init_sine": "PNN lateral scale at the start on the sine path",
    "pnn_critic_priors": "PNN critics read the prior's critic",
    "pnn_start_as_prior": "PNN starts as its prior",
    "spnn_start_as_prior": "SPNN starts as its selected prior",
    "pnn_init_from_prior": "PNN's new column starts as a copy of its prior",
    "spnn_init_from_prior": "SPNN's new column starts as a copy of its path-following prior",
    "pnn_avoidance_column": "PNN reads the avoidance column too (eq. 13, ungated)",
    "pnn_near_prior_kl": "PNN's KL term pulls toward the avoidance column near obstacles",
    "spnn_d_th": "SPNN switch distance d_th (m)",
    "spnn_d_th_sine": "SPNN switch distance d_th on the sine path (m)",
    "spnn_gate": "SPNN selector of its priors (eq. 15's hard switch, soft or learned)",
    "spnn_gate_sine": "SPNN selector on the sine path",
    "spnn_gate_temperature": "SPNN soft selector's temperature (m)",
    "spnn_gate_corridor": "SPNN gate's corridor bound c (the path column beyond abs(g) = c d_L)",
    "spnn_switch_memory": "SPNN switch's memory H (m): avoidance kept until beyond d_th + H",
    "spnn_play_memory": "SPNN evaluated with a switch memory H (m) (training unchanged)",
    "spnn_play_no_reversal": "SPNN evaluated without immediate turn reversals (training unchanged)",
    "pnn_play_no_reversal": "PNN evaluated without immediate turn reversals (training unchanged)",
    "learners_play_no_reversal": "every learner evaluated without immediate turn reversals",
    "spnn_sigma": "SPNN weight sigma of the selected prior's input",
    "spnn_own_weight": "SPNN weight tau of the new column's own input",
    "spnn_prior_kl": "SPNN actor loss + beta KL(pi || selected prior)",
    "spnn_off_path_kl": "SPNN: the same KL term over off-path copies of each minibatch",
    "spnn_off_path_kl_sine": "SPNN: the off-path KL term's weight on the sine path",
    "pnn_off_path_kl": "PNN: its KL term over off-path copies of each minibatch too",
    "pnn_off_path_kl_sine": "PNN: the off-path KL term's weight on the sine path",
    "pnn_clear_kl": "PNN: its KL term over clear-sonar copies of each minibatch too",
    "pnn_clear_kl_sine": "PNN: the clear-sonar KL term's weight on the sine path",
    "spnn_clear_kl": "SPNN: its KL term over clear-sonar copies of each minibatch too",
    "spnn_clear_kl_sine": "SPNN: the clear-sonar KL term's weight on the sine path",
    "pnn_obstacle_kl": "PNN: its KL term over drawn-obstacle copies of each minibatch too",
    "pnn_obstacle_kl_sine": "PNN: the drawn-obstacle KL term's weight on the sine path",
    "spnn_obstacle_kl": "SPNN: its KL term over drawn-obstacle copies of each minibatch too",
    "spnn_obstacle_kl_sine": "SPNN: the drawn-obstacle KL term's weight on the sine path",
    "pnn_near_corridor": "PNN's near reference only inside this fraction of d_L",
    "pnn_near_corridor_sine": "PNN's near reference's corridor bound on the sine path",
    "spnn_n_steps": "SPNN critics' return length n (n-step targets)",
    "pnn_n_steps": "PNN critics' return length n (n-step targets)",
    "pnn_n_steps_sine": "PNN critics' return length n on the sine path",
    "pf_n_steps": "path-following columns' critics' return length n (n-step targets)",
    "pf_validation_every": "path-following columns' training episodes between validation checks",
    "spnn_action_smoothness": "SPNN actor loss + lambda KL(pi(.|s) || pi(.|s'))",
    "pnn_action_smoothness": "PNN actor loss + lambda KL(pi(.|s) || pi(.|s'))",
    "exploration_epsilon": "learners: uniform action with probability epsilon in training",
    "pnn_exploration_epsilon": "PNN: uniform action with probability epsilon in training",
    "pnn_exploration_epsilon_sine": "PNN: uniform action with probability epsilon on the sine path",
    "pnn_prior_kl": "PNN actor loss + beta KL(pi || prior)",
    "mirror_augmentation": "learners: half of each minibatch mirrored left-right",
    "oa_mirror": "avoidance column: half of each minibatch mirrored left-right",
    "pnn_prior_kl_clearance": "PNN's KL term only where the nearest obstacle is farther (m)",
    "goal_obs": "goal part observed (avoidance reads it instead of the path)",
    "pnn_goal_obs": "PNN observes the goal part too",
    "goal_distance": "goal: route point ahead (m)",
    "sonar_span": "sonar span S (deg, centred ahead)",
    "sonar_sectors": "sonar sectors q",
    "heading_rule": "heading rule of the planning tasks reads",
    "los_lookahead": "LOS lookahead Delta of eq. 16 (m)",
    "oa_layout": "obstacles of the avoidance task",
    "oa_corridor": "corridor half-width of the avoidance task (m)",
    "oa_time_limit": "time limit of the avoidance task's training episodes (s)",
    "oa_budget": "avoidance column's training episodes (x the budget's)",
    "pf_sine_budget": "sine path-following column's training episodes (x the budget's)",
    "oa_offset_obs": "avoidance column observes its distance from the route",
    "prior_candidates": "source column: best of this many training runs on its validation",
    "prior_candidates_pf_straight": "straight path-following column: best of this many runs",
    "prior_retries": "source column trained again from another seed when no check passes (times)",
    "prior_keep_best_by_pf_straight": "straight path-following column's checks ranked by",
    "planning_layout": "obstacles the planning agents train on",
    "planning_obstacle_penalty": "weight of eq. 20's r_v in the learners' planning tasks",
    "planning_arrival_gate": "planning tasks end as arrival only this close to the target (m)",
    "pf_arrival_gate": "path-following columns' tasks: arrival only this close to the target (m)",
}


def path_of_env(env_id: str) -> str:
    """The path kind of an rov_envs task, ``"straight"`` or ``"sine"`` (which the per-path
    factors read), from its id, e.g. ``"rov_envs/PlanningSineDense-v0"`` -> ``"sine"``."""
    from rov_envs.sim.tasks import PATH_SINE, task_of_env

    return "sine" if task_of_env(env_id).path_kind == PATH_SINE else "straight"


def describe_value(name: str, value: Any) -> str:
    """A factor value as the report prints it."""
    if name == "prior_updates" and not value:
        return "as the update schedule"
    if name == "oa_updates" and not value:
        return "as the source columns'"
    if name in ("oa_gamma", "pf_sine_gamma", "spnn_gamma", "pnn_gamma") and value is None:
        return f"Tables 2-3's {PAPER_GAMMA}"
    if name == "prior_batch_size" and not value:
        return "as the samples per update"
    if name in ("pf_start_spread", "planning_start_spread") and value is None:
        return "as the training start noise"
    if name == "pnn_prior_kl_clearance" and value is None:
        return "every sample"
    if name == "oa_corridor" and value is None:
        return "the task's (30 m)"
    if name in ("prior_candidates_pf_straight", "prior_keep_best_by_pf_straight") and value is None:
        return "as the other source columns'"
    if name == "keep_best_route_bound" and value is None:
        return "none"
    if name == "keep_best_also" and not value:
        return "none"
    if name == "oa_time_limit" and value is None:
        return "the task's (120 s)"
    if name in ("spnn_switch_memory", "spnn_play_memory") and value is None:
        return "none (eq. 15's switch)"
    if name in SINE_PATH_FACTORS and value is None:
        return "as on the straight path"
    if name == "pnn_near_corridor" and value is None:
        return "SPNN's corridor bound"
    if name == "pnn_exploration_epsilon" and value is None:
        return "as the learners' epsilon"
    if name == "learner_target_entropy_ratio" and value is None:
        return "as the source columns'"
    if name in ("updates", "prior_updates", "oa_updates"):
        (freq, unit), steps = parse_updates(value, name)
        if unit == "episode":
            return f"{steps} per episode"
        return f"{steps} per step" if freq == 1 else f"{steps} per {freq} steps"
    if name in ("planning_arrival_gate", "pf_arrival_gate"):
        return "none" if not value else f"{value:g} m"
    if name == "goal_distance":
        return "the target point" if value is None else f"{value:g} m ahead"
    if name == "heading_rule":
        return {"path": "the path's a_c (LOS)", "goal": "the goal's bearing"}.get(value, value)
    if name == "pf_progress_weighted" and value is None:
        return "as the learners'"
    if name in ("progress_along", "planning_progress_along"):
        if value is None:
            return "as the source columns'"
        return {"path": "the path's tangent", "course": "the LOS course"}.get(value, value)
    if name == "pnn_net_arch" and not value:
        return "as the hidden layers"
    if name in ("net_arch", "pnn_net_arch"):
        return "[" + ", ".join(str(w) for w in value) + "]"
    if name in PER_PATH_FACTORS:
        return {"both": "on", "neither": "off"}.get(value, f"on the {value} path only")
    if isinstance(value, bool):
        return "on" if value else "off"
    if name == "success_reward":
        return f"{value:g}"
    return str(value)


#: Factors that refine another with a name (None: the refined factor's), and an example value.
NAMED_REFINEMENTS: dict[str, str] = {
    "spnn_gate_sine": "soft (a gate's name, or null)",
    "prior_keep_best_by_pf_straight": "discounted (a ranking, or null)",
    "spnn_keep_best_by_sine": "last (a ranking, or null)",
    "planning_progress_along": "course (path or course, or null)",
}
#: Factors that refine another with on / off (None: the refined factor's), and an example.
SWITCHED_REFINEMENTS: dict[str, str] = {
    "pf_progress_weighted": "off (on / off, or null)",
}
#: Factors that refine another with an integer (None: the refined factor's), and an example.
COUNTED_REFINEMENTS: dict[str, str] = {
    "pnn_n_steps_sine": "1 (an integer, or null)",
    "prior_candidates_pf_straight": "2 (an integer, or null)",
}


def parse_setup_changes(items: Sequence[str]) -> dict[str, Any]:
    """``["factor=value", ...]`` (the ``--set`` options) as ``{factor: value}``.

    A value is read as JSON (``keep_best=false``, ``net_arch=[128,128]``, ``control_period=0.2``)
    or else taken as a string (``updates=step:4``; ``on`` / ``off`` for a switch, as in the
    ablation's cell names), and must have the type of the factor's value
    in :data:`PAPER`. Raises ValueError naming the bad item and what was expected; the values
    themselves are then checked by :class:`TrainingSetup`.
    """
    changes: dict[str, Any] = {}
    known = [f.name for f in fields(TrainingSetup)]
    for item in items:
        name, sep, text = str(item).partition("=")
        if not sep or name not in known:
            raise ValueError(
                f"--set {item!r} is not allowed: expected factor=value with factor one of {known}"
            )
        try:
            value = json.loads(text)
        except json.JSONDecodeError:
            value = text
        default = getattr(PAPER, name)
        if isinstance(default, tuple):
            ok = isinstance(value, list) and all(
                isinstance(w, int) and not isinstance(w, bool) for w in value
            )
            value = tuple(value) if ok else value
        elif isinstance(default, bool):  # JSON true / false, or the ablation's words on / off
            value = (
                {"on": True, "off": False}.get(value, value) if isinstance(value, str) else value
            )
            ok = isinstance(value, bool)
        elif isinstance(default, float):
            ok = isinstance(value, (int, float)) and not isinstance(value, bool)
            value = float(value) if ok else value
        elif isinstance(default, int):
            ok = isinstance(value, int) and not isinstance(value, bool)
        elif name in NAMED_REFINEMENTS:  # a name, or null for the value it refines
            ok = value is None or isinstance(value, str)
        elif name in SWITCHED_REFINEMENTS:  # on / off, or null for the value it refines
            value = (
                {"on": True, "off": False}.get(value, value) if isinstance(value, str) else value
            )
            ok = value is None or isinstance(value, bool)
        elif name in COUNTED_REFINEMENTS:  # an integer, or null for the value it refines
            ok = value is None or (isinstance(value, int) and not isinstance(value, bool))
        elif default is None:  # a number, or null for "as the factor it refines"
            ok = value is None or (isinstance(value, (int, float)) and not isinstance(value, bool))
            value = float(value) if ok and value is not None else value
        elif name in PER_PATH_FACTORS:  # a path name, or true / false for both / neither
            ok = isinstance(value, (str, bool))
        else:
            ok = isinstance(value, str)
        if not ok:
            example = json.dumps(list(default) if isinstance(default, tuple) else default)
            if default is None:
                example = "1.0 (a number, or null)"
            if name in NAMED_REFINEMENTS:
                example = NAMED_REFINEMENTS[name]
            if name in COUNTED_REFINEMENTS:
                example = COUNTED_REFINEMENTS[name]
            if name in SWITCHED_REFINEMENTS:
                example = SWITCHED_REFINEMENTS[name]
            if name == "pnn_net_arch":
                example = "[255, 255] (hidden widths, or [] for net_arch's)"
            raise ValueError(
                f"--set {item!r} is not allowed: expected a value like {name}={example}"
            )
        changes[name] = value
    return changes
