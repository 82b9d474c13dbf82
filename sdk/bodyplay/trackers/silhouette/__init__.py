"""bodyplay.trackers.silhouette"""
