"""Direction following in unknown buildings (runtime): laser and instruction layers, LSTM
network, post-processing, collision guard, follower, node. Training and evaluation live in
semnav_learning.
"""
