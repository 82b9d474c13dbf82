"""bodyplay.gestures"""
