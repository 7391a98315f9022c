"""The Gymnasium API: one-env (``adapter``) and vector (``vector``) Gymnasium envs over
``GVGAIEnv``, trained on the registered curricula by name (``regimens``).

It sits above both ``gvgai_pcg.envs`` and ``gvgai_pcg.curricula``, which it builds on; the ids are
registered by ``gvgai_pcg.envs.gym_registration``, whose entry points name the modules here, so
registering them imports neither torch nor this package.
"""
