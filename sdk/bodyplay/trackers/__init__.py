"""bodyplay.trackers"""
