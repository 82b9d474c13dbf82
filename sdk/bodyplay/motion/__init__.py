"""bodyplay.motion"""
